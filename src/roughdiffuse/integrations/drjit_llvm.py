"""Which libLLVM Dr.Jit loads, and whether Mitsuba's ``llvm`` variants can run on it.

Dr.Jit loads libLLVM itself (``DRJIT_LIBLLVM_PATH``, else the system's own search). An old
one does not fail at load: Dr.Jit compiles its first kernel with it, and LLVM 15 aborts the
whole process there (``LLVM ERROR: Cannot select: ... fmaximum``), which no ``except`` can
catch (it killed a Sphinx build). So every use of an ``llvm`` variant asks first
(:func:`require_llvm`): Mitsuba's plugins (:func:`roughdiffuse.integrations.mitsuba.register`),
``stereo``'s Mitsuba renders, the export checks and the gallery; an old library is refused
with one line naming ``DRJIT_LIBLLVM_PATH`` and the version needed.

:data:`LLVM_NEEDED` is the oldest major version tested to run them: 19 runs, 15 aborts
(measured with Dr.Jit 1.5; 16 to 18 are not tested and refused).
"""

from __future__ import annotations

from .._validate import ParameterError

__all__ = ["LLVM_NEEDED", "drjit_llvm", "llvm_problem", "require_llvm"]

LLVM_NEEDED = 19
"""The oldest libLLVM major version Mitsuba's ``llvm`` variants are known to run on."""

ADVICE = (
    "install libLLVM {need} or newer (Debian: apt-get install libllvm{need}; "
    "scripts/system-deps.sh) and set DRJIT_LIBLLVM_PATH to it "
    "(e.g. /usr/lib/x86_64-linux-gnu/libLLVM.so.{need}.1), or use a scalar variant"
)


def _loaded_library() -> str | None:
    """The libLLVM file mapped into this process (Linux), for the message."""
    try:
        with open("/proc/self/maps", encoding="utf-8") as maps:
            for line in maps:
                name = line.split()[-1] if line.strip() else ""
                if "libLLVM" in name:
                    return name
    except OSError:
        pass
    return None


def drjit_llvm() -> tuple[tuple[int, int, int] | None, str | None]:
    """The version of the libLLVM Dr.Jit has loaded (loading it now if needed) and its file;
    ``(None, None)`` where Dr.Jit found none it could use (or is not installed).

    Loading it is safe: only compiling a kernel with an old one aborts.
    """
    try:
        import drjit as dr
    except ImportError:
        return None, None
    if not dr.has_backend(dr.JitBackend.LLVM):
        return None, None
    version = tuple(int(v) for v in dr.detail.llvm_version())
    if version[0] < 0:
        return None, None
    return (version[0], version[1], version[2]), _loaded_library()


def llvm_problem(
    version: tuple[int, int, int] | None = None, library: str | None = None
) -> str | None:
    """Why Mitsuba's ``llvm`` variants cannot run here (one line), or ``None`` if they can.

    ``version`` and ``library`` default to what Dr.Jit loads (:func:`drjit_llvm`); given,
    only the version rule is applied.

    >>> print(llvm_problem((15, 0, 6), "/usr/lib/libLLVM-15.so.1"))  # doctest: +ELLIPSIS
    Mitsuba's llvm variants need libLLVM 19 or newer, but Dr.Jit loads 15.0.6 (...) ...
    >>> llvm_problem((19, 1, 7)) is None
    True
    """
    if version is None and library is None:
        version, library = drjit_llvm()
    advice = ADVICE.format(need=LLVM_NEEDED)
    if version is None:
        return f"Mitsuba's llvm variants need libLLVM {LLVM_NEEDED}; Dr.Jit found none: {advice}"
    if version[0] < LLVM_NEEDED:
        where = f" ({library})" if library else ""
        shown = ".".join(str(v) for v in version)
        return (
            f"Mitsuba's llvm variants need libLLVM {LLVM_NEEDED} or newer, but Dr.Jit loads "
            f"{shown}{where}: {advice}"
        )
    return None


def require_llvm(variant: str | None) -> None:
    """Refuse an ``llvm`` Mitsuba variant this process cannot run (see :func:`llvm_problem`);
    any other variant (``scalar_*``, ``cuda_*``, ``None``) passes.

    Raises
    ------
    ValueError
        One line naming ``DRJIT_LIBLLVM_PATH`` and the libLLVM version needed.
    """
    if variant is None or not str(variant).startswith("llvm"):
        return
    problem = llvm_problem()
    if problem is not None:
        raise ParameterError(f"Mitsuba variant {variant}: {problem}")
