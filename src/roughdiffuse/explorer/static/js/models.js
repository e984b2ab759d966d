// The models the explorer offers, the parameters each one uses, and the record the GLSL
// receives. Ids match brdf.glsl and MODEL_IDS in roughdiffuse/explorer/params.py.

export const MODELS = [
  { key: "lambert", id: 0, label: "Lambert", short: "Lambert", uses: ["albedo"] },
  { key: "oren-nayar", id: 1, label: "Oren–Nayar (qualitative)", short: "Oren–Nayar qualitative", uses: ["albedo", "sigma"] },
  { key: "oren-nayar-full", id: 2, label: "Oren–Nayar (full, with interreflection)", short: "Oren–Nayar full", uses: ["albedo", "sigma"] },
  { key: "fujii", id: 3, label: "Fujii (FON)", short: "Fujii", uses: ["albedo", "roughness"] },
  { key: "eon", id: 4, label: "EON (energy-preserving)", short: "EON", uses: ["albedo", "roughness"] },
  { key: "torrance-sparrow", id: 5, label: "Torrance–Sparrow (specular)", short: "Torrance–Sparrow", uses: ["sigma", "eta", "distribution"] },
  { key: "mix", id: 6, label: "Mix: Oren–Nayar full + Torrance–Sparrow", short: "Mix", uses: ["albedo", "sigma", "weight", "eta", "distribution"] },
  { key: "lommel-seeliger", id: 7, label: "Lommel–Seeliger (lunar)", short: "Lommel–Seeliger", uses: ["albedo"] },
  { key: "lunar-lambert", id: 8, label: "Lunar-Lambert (McEwen)", short: "Lunar-Lambert", uses: ["albedo", "limb"] },
  { key: "burley", id: 9, label: "Burley 2012 (Disney)", short: "Burley", uses: ["albedo", "roughness"] },
  { key: "frostbite", id: 10, label: "Frostbite (renormalised Burley)", short: "Frostbite", uses: ["albedo", "roughness"] },
  { key: "burley-2015", id: 11, label: "Burley 2015 (diffuse + retro-reflection)", short: "Burley 2015", uses: ["albedo", "roughness"] },
  { key: "hammon", id: 12, label: "Hammon (GGX diffuse)", short: "Hammon", uses: ["albedo", "alpha"] },
  { key: "chan", id: 13, label: "Chan (Call of Duty: WWII)", short: "Chan", uses: ["albedo", "alpha"] },
  { key: "lambert-sphere", id: 14, label: "d'Eon Lambertian spheres", short: "Lambert spheres", uses: ["albedo", "variant"] },
  { key: "hapke", id: 15, label: "Hapke (planetary)", short: "Hapke", uses: ["albedo", "b0", "hh", "hg", "thetaBar"] },
  { key: "minnaert", id: 16, label: "Minnaert (planetary)", short: "Minnaert", uses: ["albedo", "k"] },
];

export const BY_KEY = Object.fromEntries(MODELS.map((m) => [m.key, m]));

/** Default UI state of one model slot (σ in degrees, as on the sliders). */
export function defaultState(key = "oren-nayar") {
  return {
    model: key,
    albedo: [0.8, 0.8, 0.8],
    sigmaDeg: 20,
    roughness: 0.5,
    eta: 1.5,
    weight: 0.1,
    limb: 0.5,
    distribution: "gaussian",
    alpha: 0.3,
    variant: "full",
    k: 0.7,
    b0: 0.8,
    hh: 0.06,
    hg: -0.3,
    thetaBarDeg: 20,
  };
}

/**
 * The record the GLSL receives (brdf.glsl's RDParams). Accepts the UI state (sigmaDeg) or a
 * record with sigma in radians already (as the tests send it).
 */
export function gpuParams(s) {
  const m = BY_KEY[s.model];
  if (!m) throw new Error(`unknown model ${JSON.stringify(s.model)}`);
  const sigma = s.sigma !== undefined ? s.sigma : (s.sigmaDeg * Math.PI) / 180;
  return {
    model: m.id,
    albedo: Float32Array.from(s.albedo ?? [0.8, 0.8, 0.8]),
    sigma,
    roughness: s.roughness ?? 0,
    eta: s.eta ?? 1.5,
    weight: s.weight ?? 0,
    limb: s.limb ?? 0.5,
    distribution: (s.distribution ?? "gaussian") === "beckmann" ? 1 : 0,
    alpha: s.alpha ?? 0.3,
    variant: (s.variant ?? "full") === "fast" ? 1 : 0,
    k: s.k ?? 1.0,
    b0: s.b0 ?? 0.0,
    hh: s.h ?? s.hh ?? 0.1,
    hg: s.g ?? s.hg ?? 0.0,
    thetaBar: s.theta_bar !== undefined ? s.theta_bar : ((s.thetaBarDeg ?? 0) * Math.PI) / 180,
  };
}
