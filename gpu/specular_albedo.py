"""How much light the Principled BSDF's glossy layer reflects, over all directions: the
table its shaders read (shaders/specular.glsl specular_albedo, a texture the context
makes once: GLContext.use_specular_albedo) and the same sums on the host for the colour a
surface bounces light with (Scene.surface_colours).

The table holds, per Blender roughness and cosine toward the viewer, the single-scattering
GGX lobe's albedo (shaders/specular.glsl ggx_brdf: height-correlated Smith) with a Fresnel
of 1, and the shares of it that the Fresnel's rise toward grazing adds: Schlick's (a
metal's) and a dielectric's of IOR 1.5 (Principled's default); a second table holds their
means over directions, for light that arrives from all around. Light the
single-scattering lobe loses comes back as Cycles' multiple-scattering GGX returns it
(Fdez-Agüera 2019).
"""
import functools

import numpy as np

STEPS = 16
"""Table rows (roughness 0..1) and columns (cosine 0..1), sampled at both ends."""
RASTER_UNIT = 8
"""The texture unit the raster passes (G-buffer, RSMs) read the table from (surface images: 7)."""
SAMPLES = 32
"""Half-vector samples along each of the two axes of the lobe a table entry sums."""
TABLE_IOR = 1.5
MEAN_STEPS = 16
"""Midpoints in cos² of the tables' cosine-weighted mean over directions."""


def _dielectric_fresnel(c, eta):
    g = np.sqrt(eta * eta - 1.0 + c * c)
    a, b = (g - c) / (g + c), (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
    return 0.5 * a * a * (1.0 + b * b)


def _lobe_terms(roughness, nv, u1, u2):
    """The lobe's albedo toward cos `nv` with a Fresnel of 1, and the parts Schlick's rise
    and the dielectric's rise weigh it by (half vectors drawn from GGX at `u1`, `u2`)."""
    a2 = max(roughness * roughness, 1e-3) ** 2
    cos_h = np.sqrt((1.0 - u1) / (1.0 + (a2 - 1.0) * u1))  # GGX half vectors, pdf D cos_h
    sin_h = np.sqrt(1.0 - cos_h * cos_h)
    vh = sin_h * np.cos(2 * np.pi * u2) * np.sqrt(1.0 - nv * nv) + cos_h * nv
    nl = 2.0 * vh * cos_h - nv
    kept = (nl > 0.0) & (vh > 0.0)
    nl, vh, cos_h = nl[kept], vh[kept], cos_h[kept]
    visibility = 0.5 / (nl * np.sqrt(nv * nv * (1 - a2) + a2) + nv * np.sqrt(nl * nl * (1 - a2) + a2))
    weight = visibility * nl * 4.0 * vh / cos_h / len(u1)
    f0 = ((TABLE_IOR - 1.0) / (TABLE_IOR + 1.0)) ** 2
    rise = (_dielectric_fresnel(vh, TABLE_IOR) - f0) / (1.0 - f0)
    return weight.sum(), (weight * (1.0 - vh) ** 5).sum(), (weight * rise).sum()


@functools.cache
def albedo_tables():
    """Per roughness (rows, STEPS of them) the lobe's terms (_lobe_terms) at STEPS cosines
    (columns), (STEPS, STEPS, 3), and their cosine-weighted mean over directions (MEAN_STEPS
    midpoints in cos²), (STEPS, 3): float64."""
    u = (np.arange(SAMPLES) + 0.5) / SAMPLES
    u1, u2 = (a.ravel() for a in np.meshgrid(u, u, indexing="ij"))
    roughnesses = np.linspace(0.0, 1.0, STEPS)
    table = np.array([[_lobe_terms(r, nv, u1, u2) for nv in np.maximum(np.linspace(0.0, 1.0, STEPS), 1e-3)]
                      for r in roughnesses])
    cosines = np.sqrt((np.arange(MEAN_STEPS) + 0.5) / MEAN_STEPS)
    means = np.array([np.mean([_lobe_terms(r, nv, u1, u2) for nv in cosines], axis=0) for r in roughnesses])
    return table, means


def texture_rows():
    """The tables as one float32 image (STEPS rows of roughness, STEPS + 1 columns, RGB):
    the lobe's terms at each cosine, then their mean over directions in the last column
    (shaders/specular.glsl reads it with bilinear filtering)."""
    table, means = albedo_tables()
    return np.concatenate([table, means[:, None, :]], axis=1).astype(np.float32)


def _read(roughness, nv=None):
    """The table read bilinearly at each (roughness, cosine), or its mean over directions
    linearly at each roughness (nv None), as specular.glsl's texture reads do."""
    table, means = albedo_tables()
    x = np.clip(np.asarray(roughness, np.float64), 0.0, 1.0) * (STEPS - 1)
    x0 = np.minimum(x.astype(int), STEPS - 2)
    fx = (x - x0)[..., None]
    if nv is None:
        return means[x0] * (1 - fx) + means[x0 + 1] * fx
    y = np.clip(np.asarray(nv, np.float64), 0.0, 1.0) * (STEPS - 1)
    y0 = np.minimum(y.astype(int), STEPS - 2)
    fy = (y - y0)[..., None]
    top = table[x0, y0] * (1 - fy) + table[x0, y0 + 1] * fy
    bottom = table[x0 + 1, y0] * (1 - fy) + table[x0 + 1, y0 + 1] * fy
    return top * (1 - fx) + bottom * fx


def _albedo(f0, metallic, terms):
    """A layer's albedo from the lobe's terms (specular.glsl layer_albedo)."""
    f0 = np.asarray(f0, np.float64)
    white = terms[..., 0:1]
    rise = terms[..., 2:3] + (terms[..., 1:2] - terms[..., 2:3]) * np.asarray(metallic, np.float64)[..., None]
    f90 = np.clip(50.0 * f0.max(axis=-1, keepdims=True), 0.0, 1.0)
    single = f0 * (white - rise) + rise * f90
    lost = 1.0 - white
    average = f0 + (1.0 - f0) / 21.0
    return single + single * average * lost / (1.0 - average * lost)


def specular_albedo(f0, metallic, roughness, nv):
    """The share of uniform light a glossy layer of F0 `f0` (..., 3), metallic share and
    Blender roughness reflects toward cos `nv` (shaders/specular.glsl specular_albedo): a
    layer of F0 0 reflects nothing."""
    return _albedo(f0, metallic, _read(roughness, nv))


def bounce_colours(albedo, f0, metallic, roughness):
    """What surfaces of diffuse colour `albedo` (T, 3) under glossy layers (F0 (T, 3),
    metallic (T,), roughness (T,)) send on of light arriving from every direction, counted
    as diffuse: the diffuse the layer keeps and what it reflects, both with the layer's
    albedo meaned over directions (a light map's texel sends the layer's along its lobe:
    shaders/rsm_surface.glsl)."""
    layer = _albedo(f0, metallic, _read(roughness))
    kept = 1.0 - np.clip(layer.max(axis=1), 0.0, 1.0)
    return np.asarray(albedo, np.float64) * kept[:, None] + layer
