#!/usr/bin/env bash
# System packages the test suite and the docs need (make test, make docs): Chromium (explorer
# tests, Playwright drives it) and libLLVM 19 (Mitsuba 3's llvm_ad_rgb variant: libLLVM 15
# aborts it, roughdiffuse.integrations.drjit_llvm); glslang-tools (glslangValidator compiles
# the GLSL MaterialX generates from exported .mtlx files); npm (three.js for the test of the
# exported GLSL, `npm ci` in tests/js). Installed with apt-get when missing and
# running as root; otherwise named, with the command to run, and the script fails.
#
# The kernel's limit on memory mappings per process (vm.max_map_count, 65530 by default) is
# raised to 262144 when root: Numba and XLA map three regions (code, constants, data) per
# compiled module, and a test worker that compiles the kernels of every model comes within
# 10 % of the default in a full run (a mapping that fails then aborts XLA or LLVM). Otherwise
# the script says how.
set -euo pipefail
maps_wanted=262144
maps_now=$(cat /proc/sys/vm/max_map_count 2>/dev/null || echo "$maps_wanted")
if [ "$maps_now" -lt "$maps_wanted" ]; then
  if [ "$(id -u)" -eq 0 ] && (echo "$maps_wanted" > /proc/sys/vm/max_map_count) 2>/dev/null; then
    echo "vm.max_map_count raised from $maps_now to $maps_wanted (memory mappings per process)"
  else
    echo "note: vm.max_map_count is $maps_now; the full test suite (make test SLOW=1) needs" \
      "$maps_wanted: sudo sysctl -w vm.max_map_count=$maps_wanted" >&2
  fi
fi
need=()
command -v chromium >/dev/null 2>&1 || need+=(chromium)
ls /usr/lib/*/libLLVM.so.19* /usr/lib/*/libLLVM-19.so >/dev/null 2>&1 || need+=(libllvm19)
command -v glslangValidator >/dev/null 2>&1 || need+=(glslang-tools)
command -v npm >/dev/null 2>&1 || need+=(npm)
[ ${#need[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; then
  echo "installing system packages: ${need[*]}"
  apt-get update -q >/dev/null
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${need[@]}" >/dev/null
else
  echo "roughdiffuse tests and docs need these system packages: ${need[*]}" >&2
  echo "install them as root:  apt-get install -y ${need[*]}" >&2
  exit 1
fi
