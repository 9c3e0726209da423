"""Blender 5.0's Sky Texture models in numpy, evaluated as Cycles evaluates them, from plain
values (no bpy): the physical skies (single and multiple scattering) through the 512 x 256
XYZ texture Cycles precomputes and its sun disc, and Preetham's analytic sky.

Ported from Blender's intern/sky/source/sky_single_scattering.cpp,
sky_multiple_scattering.cpp (Fernando García Liñán's spectral sky with its
multiple-scattering fit and Hillaire's energy-conserving integration), sky_math.h, and
Cycles' scene/shader_nodes.cpp (SkyTextureNode's precomputation, simplify_settings) and
kernel/svm/sky.h (the texture's look-up, the sun disc with its limb darkening, the ground).
The texture's texels are computed on demand, only those a look-up reads: a 64 x 128 map
reads a quarter of them."""
import math

import numpy as np

XYZ_TO_REC709 = np.array([[3.2409699, -1.5373832, -0.4986108], [-0.9692436, 1.8759675, 0.0415551],
                          [0.0556301, -0.2039770, 1.0569715]])
"""Cycles' xyz_to_rgb with Blender's default OCIO config: XYZ with a D65 white (its
cie_xyz_d65_interchange role) to linear Rec.709; a fit to Cycles' sky renders gives it to
1e-4."""

TEXTURE_SIZE = (256, 512)
"""The (height, width) of the sky texture Cycles precomputes (its SkyLoader)."""


def xyz_to_rec709(xyz):
    """Cycles' xyz_to_rgb_clamped: linear Rec.709, negatives clipped."""
    return np.maximum(np.asarray(xyz) @ XYZ_TO_REC709.T, 0.0)


def wrapped_sun_position(elevation, rotation):
    """The sun's (elevation in [-pi/2, pi/2], rotation) as Cycles' simplify_settings wraps
    them (it also turns the rotation around: 2 pi - rotation, which its look-up expects)."""
    elevation = math.fmod(elevation, 2 * math.pi)
    if abs(elevation) >= math.pi:
        elevation -= math.copysign(2.0, elevation) * math.pi
    if elevation >= math.pi / 2 or elevation <= -math.pi / 2:
        elevation = math.copysign(math.pi, elevation) - elevation
        rotation += math.pi
    rotation = math.fmod(rotation, 2 * math.pi)
    if rotation < 0:
        rotation += 2 * math.pi
    return elevation, 2 * math.pi - rotation


class PhysicalSky:
    """The Single and Multiple Scattering skies: the texture Cycles precomputes (XYZ),
    looked up per direction, plus the sun disc from its two precomputed pixels."""

    def __init__(self, multiple_scattering, sun_disc, sun_size, sun_intensity, sun_elevation, sun_rotation,
                 altitude, air_density, aerosol_density, ozone_density):
        self.multiple_scattering = multiple_scattering
        self.sun_elevation, self.sun_rotation = wrapped_sun_position(sun_elevation, sun_rotation)
        self.angular_diameter = sun_size if sun_disc else -1.0
        self.sun_intensity = sun_intensity
        atmosphere = (air_density, aerosol_density, ozone_density)
        if multiple_scattering:
            self.atmosphere = MultipleScatteringAtmosphere(altitude, *atmosphere)
        else:
            self.atmosphere = SingleScatteringAtmosphere(altitude, *atmosphere)
        self.earth_intersection_angle = -(math.pi / 2 - math.asin(
            MultipleScatteringAtmosphere.EARTH_RADIUS / (MultipleScatteringAtmosphere.EARTH_RADIUS + altitude / 1000)))
        self.pixel_bottom, self.pixel_top = self.atmosphere.sun_pixels(self.sun_elevation, max(sun_size, 0.0))
        self.texture = np.full(TEXTURE_SIZE + (3,), np.nan)

    @property
    def sun_direction(self):
        """The unit vector toward the sun's centre."""
        e, r = self.sun_elevation, 2 * math.pi - self.sun_rotation
        return np.array([math.sin(r) * math.cos(e), math.cos(r) * math.cos(e), math.sin(e)])

    def radiance(self, directions, sun=True):
        """Linear Rec.709 radiance along unit `directions` (..., 3): the sky, and the sun
        disc where `sun`."""
        d = np.asarray(directions, dtype=np.float64)
        elevation = math.pi / 2 - np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        x = np.mod((-np.arctan2(d[..., 1], d[..., 0]) - math.pi / 2 + self.sun_rotation) / (2 * math.pi), 1.0)
        below = d[..., 2] < 0
        if self.multiple_scattering:
            y = np.sqrt(np.abs(elevation) / (math.pi / 2)) * np.sign(elevation) * 0.5 + 0.5
            rgb = xyz_to_rec709(self.lookup(x, y))
        else:  # the ground fades to black below the horizon
            y = np.where(below, 0.508, np.sqrt(np.maximum(elevation, 0.0) / (math.pi / 2)) * 0.5 + 0.5)
            fade = np.where(below, np.maximum(1.0 + d[..., 2] * 2.5, 0.0) ** 3, 1.0)
            rgb = xyz_to_rec709(self.lookup(x, y)) * fade[..., None]
        if sun:
            rgb = rgb + self.sun_radiance(d)
        return rgb

    def sun_radiance(self, directions):
        """The sun disc's radiance (limb-darkened, between its bottom and top pixels),
        zero off the disc and where the Earth hides it."""
        d = np.asarray(directions, dtype=np.float64)
        shape = d.shape[:-1] + (3,)
        if self.angular_diameter < 0:
            return np.zeros(shape)
        half = self.angular_diameter / 2
        angle = _precise_angle(d, self.sun_direction)
        elevation = math.pi / 2 - np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        inside = (angle < half) & (elevation > self.earth_intersection_angle)
        if not self.multiple_scattering:
            inside &= d[..., 2] >= 0
        y = ((elevation - self.sun_elevation) / self.angular_diameter + 0.5)[..., None]
        xyz = self.pixel_bottom + y * (self.pixel_top - self.pixel_bottom)
        limb = 1.0 - 0.6 * (1.0 - np.sqrt(np.maximum(1.0 - (angle / half) ** 2, 0.0)))
        return np.where(inside[..., None], xyz_to_rec709(xyz) * limb[..., None] * self.sun_intensity, 0.0)

    def sun_power(self, rings=48, sectors=96):
        """The sun disc's radiance integrated over its solid angle (irradiance facing it),
        by quadrature over the disc: what a texel holding the disc must carry."""
        if self.angular_diameter <= 0:
            return np.zeros(3)
        half = self.angular_diameter / 2
        alpha = (np.arange(rings) + 0.5) / rings * half
        psi = (np.arange(sectors) + 0.5) / sectors * 2 * math.pi
        centre = self.sun_direction
        up = np.array([0.0, 0.0, 1.0]) if abs(centre[2]) < 0.999 else np.array([1.0, 0.0, 0.0])
        across = np.cross(up, centre)
        across /= np.linalg.norm(across)
        along = np.cross(centre, across)
        a, p = np.meshgrid(alpha, psi, indexing="ij")
        directions = (np.cos(a)[..., None] * centre + np.sin(a)[..., None] *
                      (np.cos(p)[..., None] * across + np.sin(p)[..., None] * along))
        weights = np.sin(a) * (half / rings) * (2 * math.pi / sectors)
        return np.einsum("ij,ijc->c", weights, self.sun_radiance(directions))

    def lookup(self, x, y):
        """The texture at (x, y) in [0, 1] (y = 0 its bottom row), bilinear with clamped
        edges as Cycles' linear EXTEND look-up, computing the texels it needs."""
        height, width = TEXTURE_SIZE
        fx, fy = x * width - 0.5, y * height - 0.5
        x0, y0 = np.floor(fx).astype(np.int64), np.floor(fy).astype(np.int64)
        tx, ty = (fx - x0)[..., None], (fy - y0)[..., None]
        x1, y1 = np.clip(x0 + 1, 0, width - 1), np.clip(y0 + 1, 0, height - 1)
        x0, y0 = np.clip(x0, 0, width - 1), np.clip(y0, 0, height - 1)
        self._fill(np.concatenate([r.ravel() for r in (y0, y0, y1, y1)]),
                   np.concatenate([c.ravel() for c in (x0, x1, x0, x1)]))
        t = self.texture
        return (t[y0, x0] * (1 - tx) + t[y0, x1] * tx) * (1 - ty) + (t[y1, x0] * (1 - tx) + t[y1, x1] * tx) * ty

    def _fill(self, rows, columns):
        """Computes the texels at (rows, columns) not yet computed (the texture is mirrored
        about its middle column, as Cycles computes half of it)."""
        width = TEXTURE_SIZE[1]
        columns = np.minimum(columns, width - 1 - columns)
        missing = np.isnan(self.texture[rows, columns, 0])
        if not np.any(missing):
            return
        flat = np.unique(rows[missing] * width + columns[missing])
        rows, columns = flat // width, flat % width
        xyz = self.atmosphere.texels(rows, columns, self.sun_elevation)
        self.texture[rows, columns] = xyz
        self.texture[rows, width - 1 - columns] = xyz


def _precise_angle(a, b):
    """Cycles' precise_angle: the angle between unit vectors, accurate when small."""
    return 2.0 * np.arctan2(np.linalg.norm(a - b, axis=-1), np.linalg.norm(a + b, axis=-1))


def _ray_sphere_intersection(origin, direction, radius):
    """sky_math.h's ray_sphere_intersection, per ray: the distance, or -1 for none."""
    b = np.einsum("...i,...i", origin, direction)
    c = np.einsum("...i,...i", origin, origin) - radius * radius
    d = b * b - c
    root = np.sqrt(np.maximum(d, 0.0))
    t = np.where(d >= b * b, -b + root, -b - root)
    return np.where(((c > 0) & (b > 0)) | (d < 0), -1.0, t)


class SingleScatteringAtmosphere:
    """sky_single_scattering.cpp: Rayleigh and Mie single scattering over 21 wavelengths,
    ozone absorbing, the sun's optical depth by Gauss-Laguerre quadrature."""
    RAYLEIGH_SCALE, MIE_SCALE, MIE_COEFF, MIE_G = 8e3, 1.2e3, 2e-5, 0.76
    EARTH_RADIUS, ATMOSPHERE_RADIUS, STEPS = 6360e3, 6420e3, 32
    STEP_LAMBDA = 20.0
    IRRADIANCE = np.array([
        1.45756829855592995315, 1.56596305559738380175, 1.65148449067670455293, 1.71496242737209314555,
        1.75797983805020541226, 1.78256407885924539336, 1.79095108475838560302, 1.78541550133410664714,
        1.76815554864306845317, 1.74122069647250410362, 1.70647127164943679389, 1.66556087452739887134,
        1.61993437242451854274, 1.57083597368892080581, 1.51932335059305478886, 1.46628494965214395407,
        1.41245852740172450623, 1.35844961970384092709, 1.30474913844739281998, 1.25174963272610817455,
        1.19975998755420620867])
    RAYLEIGH_COEFF = np.array([
        5.424820087636473e-05, 4.418549866505454e-05, 3.635151910165377e-05, 3.017929012024763e-05,
        2.526320226989157e-05, 2.130859310621843e-05, 1.809838025320633e-05, 1.547057129129042e-05,
        1.330284977336850e-05, 1.150184784075764e-05, 9.99557429990163e-06, 8.72799973630707e-06,
        7.65513700977967e-06, 6.74217203751443e-06, 5.96134125832052e-06, 5.29034598065810e-06,
        4.71115687557433e-06, 4.20910481110487e-06, 3.77218381260133e-06, 3.39051255477280e-06,
        3.05591531679811e-06])
    OZONE_COEFF = np.array([
        3.25126849861e-09, 5.85395365047e-09, 1.977191155085e-08, 7.309568762914e-08, 2.0084561514287e-07,
        4.0383958096161e-07, 6.3551335912363e-07, 9.6707041180970e-07, 1.54797400424410e-06,
        2.09038647223331e-06, 2.46128056164565e-06, 2.73551299461512e-06, 2.15125863128643e-06,
        1.59051840791988e-06, 1.12356197979857e-06, 7.3527551487574e-07, 4.6450130357806e-07,
        3.3096079921048e-07, 2.2512612292678e-07, 1.4879129266490e-07, 1.6828623364192e-07])
    CMF_XYZ = np.array([
        [0.00136800000, 0.00003900000, 0.00645000100], [0.01431000000, 0.00039600000, 0.06785001000],
        [0.13438000000, 0.00400000000, 0.64560000000], [0.34828000000, 0.02300000000, 1.74706000000],
        [0.29080000000, 0.06000000000, 1.66920000000], [0.09564000000, 0.13902000000, 0.81295010000],
        [0.00490000000, 0.32300000000, 0.27200000000], [0.06327000000, 0.71000000000, 0.07824999000],
        [0.29040000000, 0.95400000000, 0.02030000000], [0.59450000000, 0.99500000000, 0.00390000000],
        [0.91630000000, 0.87000000000, 0.00165000100], [1.06220000000, 0.63100000000, 0.00080000000],
        [0.85444990000, 0.38100000000, 0.00019000000], [0.44790000000, 0.17500000000, 0.00002000000],
        [0.16490000000, 0.06100000000, 0.00000000000], [0.04677000000, 0.01700000000, 0.00000000000],
        [0.01135916000, 0.00410200000, 0.00000000000], [0.00289932700, 0.00104700000, 0.00000000000],
        [0.00069007860, 0.00024920000, 0.00000000000], [0.00016615050, 0.00006000000, 0.00000000000],
        [0.00004150994, 0.00001499000, 0.00000000000]])
    QUADRATURE_NODES = np.array([0.006811185292, 0.03614807107, 0.09004346519, 0.1706680068, 0.2818362161,
                                 0.4303406404, 0.6296271457, 0.9145252695])
    QUADRATURE_WEIGHTS = np.array([0.01750893642, 0.04135477391, 0.06678839063, 0.09507698807, 0.1283416365,
                                   0.1707430204, 0.2327233347, 0.3562490486])

    def __init__(self, altitude, air_density, aerosol_density, ozone_density):
        self.altitude = min(max(altitude, 1.0), 59999.0)
        self.density_scale = np.array([air_density, aerosol_density, ozone_density])

    def densities(self, height):
        """(rayleigh, mie, ozone) density factors at heights (...) in m: (..., 3)."""
        return np.stack([np.exp(-height / self.RAYLEIGH_SCALE), np.exp(-height / self.MIE_SCALE),
                         np.maximum(0.0, 1.0 - np.abs(height - 25000.0) / 15000.0)], axis=-1)

    def _atmosphere_distance(self, origin, direction):
        b = 2.0 * np.einsum("...i,...i", direction, origin)
        c = np.einsum("...i,...i", origin, origin) - self.ATMOSPHERE_RADIUS ** 2
        return (-b + np.sqrt(b * b - 4.0 * c)) / 2.0

    def optical_depth(self, origin, direction):
        """ray_optical_depth: (rayleigh, mie, ozone) optical depth factors from `origin`
        (..., 3) along `direction` to the top of the atmosphere, (..., 3)."""
        length = self._atmosphere_distance(origin, direction)
        length = np.asarray(length)
        points = origin[..., None, :] + self.QUADRATURE_NODES[:, None] * direction * length[..., None, None]
        height = np.linalg.norm(points, axis=-1) - self.EARTH_RADIUS
        return np.einsum("...kc,k->...c", self.densities(height), self.QUADRATURE_WEIGHTS) * length[..., None]

    def spectrum_to_xyz(self, spectrum):
        return spectrum @ self.CMF_XYZ * self.STEP_LAMBDA

    def texels(self, rows, columns, sun_elevation):
        """The texture's XYZ at texel (rows, columns), columns in the half Cycles computes:
        the sky above the horizon, black below."""
        half_height, width = TEXTURE_SIZE[0] // 2, TEXTURE_SIZE[1]
        xyz = np.zeros(rows.shape + (3,))
        above = rows > half_height
        latitude = math.pi / 2 * (rows[above] / half_height - 1.0) ** 2
        longitude = 2 * math.pi / width * columns[above] - math.pi
        directions = np.stack([np.cos(latitude) * np.cos(longitude), np.cos(latitude) * np.sin(longitude),
                               np.sin(latitude)], axis=-1)
        sun = np.array([math.cos(sun_elevation), 0.0, math.sin(sun_elevation)])
        xyz[above] = self.spectrum_to_xyz(self.single_scattering(directions, sun))
        return xyz

    def single_scattering(self, directions, sun):
        """single_scattering: the in-scattered spectrum along each of `directions` (n, 3)
        from the camera at its altitude, (n, 21)."""
        origin = np.array([0.0, 0.0, self.EARTH_RADIUS + self.altitude])
        length = self._atmosphere_distance(origin, directions)
        segment_length = length / self.STEPS
        mu = directions @ sun
        g2 = self.MIE_G ** 2
        phase_rayleigh = 0.1875 / math.pi * (1.0 + mu * mu)
        phase_mie = 3.0 * (1.0 - g2) * (1.0 + mu * mu) / (
            8.0 * math.pi * (2.0 + g2) * (1.0 + g2 - 2.0 * self.MIE_G * mu) ** 1.5)
        optical_depth = np.zeros(directions.shape[:-1] + (3,))
        spectrum = np.zeros(directions.shape[:-1] + (21,))
        extinction = np.stack([self.RAYLEIGH_COEFF, np.full(21, 1.11 * self.MIE_COEFF), self.OZONE_COEFF])
        for step in range(self.STEPS):
            points = origin + directions * ((step + 0.5) * segment_length)[:, None]
            density = self.density_scale * self.densities(np.linalg.norm(points, axis=-1) - self.EARTH_RADIUS)
            optical_depth += segment_length[:, None] * density
            if sun[2] >= 0:
                lit = np.ones(len(points), dtype=bool)
            else:
                b = 2.0 * points @ sun
                lit = b * b - 4.0 * (np.einsum("ij,ij->i", points, points) - self.EARTH_RADIUS ** 2) < 0
            if not np.any(lit):
                continue
            total = optical_depth[lit] + self.density_scale * self.optical_depth(points[lit], sun)
            attenuation = np.exp(-total @ extinction)
            scattering = (phase_rayleigh[lit] * density[lit, 0])[:, None] * self.RAYLEIGH_COEFF + \
                (phase_mie[lit] * density[lit, 1] * self.MIE_COEFF)[:, None]
            spectrum[lit] += attenuation * scattering * self.IRRADIANCE * segment_length[lit, None]
        return spectrum

    def sun_pixels(self, sun_elevation, angular_diameter):
        """SKY_single_scattering_precompute_sun: the disc's XYZ at its lowest and highest
        points (black when below the horizon)."""
        half = angular_diameter / 2
        solid_angle = 2 * math.pi * (1 - math.cos(half))
        top = max(sun_elevation + half, 0.0)
        if top <= 0 or solid_angle <= 0:
            return np.zeros(3), np.zeros(3)
        origin = np.array([0.0, 0.0, self.EARTH_RADIUS + self.altitude])
        pixels = []
        for elevation in (max(sun_elevation - half, 0.0), top):
            direction = np.array([math.cos(elevation), 0.0, math.sin(elevation)])
            depth = self.optical_depth(origin, direction)
            transmittance = self.RAYLEIGH_COEFF * depth[0] * self.density_scale[0] + \
                1.11 * self.MIE_COEFF * depth[1] * self.density_scale[1]
            pixels.append(self.spectrum_to_xyz(self.IRRADIANCE * np.exp(-transmittance) / solid_angle))
        return pixels[0], pixels[1]


class MultipleScatteringAtmosphere:
    """sky_multiple_scattering.cpp: 4 wavelengths, a transmittance LUT, the fitted
    multiple scattering and the ground's second order, integrated as Hillaire does."""
    EARTH_RADIUS, ATMOSPHERE_THICKNESS = 6371.0, 100.0
    ATMOSPHERE_RADIUS = EARTH_RADIUS + ATMOSPHERE_THICKNESS
    TRANSMITTANCE_STEPS, IN_SCATTERING_STEPS = 64, 64
    TRANSMITTANCE_RES_X, TRANSMITTANCE_RES_Y = 256, 64
    G = 0.8
    GROUND_ALBEDO = 0.3
    SUN_SPECTRAL_IRRADIANCE = np.array([1.679, 1.828, 1.986, 1.307])
    MOLECULAR_SCATTERING_COEFFICIENT_BASE = np.array([6.605e-3, 1.067e-2, 1.842e-2, 3.156e-2])
    OZONE_ABSORPTION_CROSS_SECTION = np.array([3.472e-25, 3.914e-25, 1.349e-25, 11.03e-27])
    OZONE_MEAN_DOBSON = 334.5
    AEROSOL_ABSORPTION_CROSS_SECTION = np.array([2.8722e-24, 4.6168e-24, 7.9706e-24, 1.3578e-23])
    AEROSOL_SCATTERING_CROSS_SECTION = np.array([1.5908e-22, 1.7711e-22, 2.0942e-22, 2.4033e-22])
    AEROSOL_BASE_DENSITY, AEROSOL_BACKGROUND_DENSITY, AEROSOL_HEIGHT_SCALE = 1.3681e20, 2e6, 0.73
    SPECTRAL_XYZ = np.array([[53.386917738564668023, 22.981337506691024754, 0.0],
                             [43.904844466369358263, 71.347795700053393866, 0.102506867965741307],
                             [1.6137278251608962005, 18.422960591455485011, 31.742921188390805758],
                             [20.762668673810577145, 2.3614213523314368527, 110.48009643252140334]])
    MULTIPLE_SCATTERING_FIT = 0.02 * np.array([0.217, 0.347, 0.594, 1.0])

    def __init__(self, altitude, air_density, aerosol_density, ozone_density):
        self.altitude = min(max(altitude, 1.0), 99999.0) / 1000.0  # km
        self.air_density, self.aerosol_density, self.ozone_density = air_density, aerosol_density, ozone_density
        self._transmittance_lut = None

    def extinction_and_scattering(self, altitude):
        """(extinction, molecular scattering, aerosol scattering) at altitudes (...) in km,
        each (..., 4)."""
        aerosol = self.AEROSOL_BASE_DENSITY * (np.exp(-altitude / self.AEROSOL_HEIGHT_SCALE) +
                                               self.AEROSOL_BACKGROUND_DENSITY / self.AEROSOL_BASE_DENSITY)
        aerosol = (aerosol * self.aerosol_density)[..., None]
        log_h = np.log(np.maximum(altitude, 1e-4))
        ozone = 3.78547397e20 * np.exp(-(log_h - 3.22261) ** 2 * 5.55555555 - log_h)
        molecular_absorption = self.OZONE_ABSORPTION_CROSS_SECTION * self.OZONE_MEAN_DOBSON * \
            (ozone * self.ozone_density)[..., None]
        molecular_scattering = self.MOLECULAR_SCATTERING_COEFFICIENT_BASE * \
            (np.exp(-0.07771971 * altitude ** 1.16364243) * self.air_density)[..., None]
        aerosol_scattering = self.AEROSOL_SCATTERING_CROSS_SECTION * aerosol
        extinction = self.AEROSOL_ABSORPTION_CROSS_SECTION * aerosol + aerosol_scattering + \
            molecular_absorption + molecular_scattering
        return extinction, molecular_scattering, aerosol_scattering

    def transmittance(self, cos_theta, normalized_altitude):
        """get_transmittance: to the sun at zenith cosine `cos_theta` from a normalized
        altitude (arrays, broadcast), ray-marched, (..., 4)."""
        cos_theta, normalized_altitude = np.broadcast_arrays(np.asarray(cos_theta, dtype=np.float64),
                                                             np.asarray(normalized_altitude, dtype=np.float64))
        sun = np.stack([-np.sqrt(np.maximum(1 - cos_theta ** 2, 0.0)), np.zeros_like(cos_theta), cos_theta], -1)
        origin = np.zeros(cos_theta.shape + (3,))
        origin[..., 2] = self.EARTH_RADIUS + normalized_altitude * self.ATMOSPHERE_THICKNESS
        step = _ray_sphere_intersection(origin, sun, self.ATMOSPHERE_RADIUS) / self.TRANSMITTANCE_STEPS
        depth = np.zeros(cos_theta.shape + (4,))
        for i in range(self.TRANSMITTANCE_STEPS):
            points = origin + sun * ((i + 0.5) * step)[..., None]
            altitude = np.maximum(np.linalg.norm(points, axis=-1) - self.EARTH_RADIUS, 0.0)
            depth += self.extinction_and_scattering(altitude)[0] * step[..., None]
        return np.exp(-depth)

    @property
    def transmittance_lut(self):
        """precompute_lut: transmittance by (altitude row, sun cosine column)."""
        if self._transmittance_lut is None:
            u = np.arange(self.TRANSMITTANCE_RES_X) / (self.TRANSMITTANCE_RES_X - 1)
            v = np.arange(self.TRANSMITTANCE_RES_Y) / (self.TRANSMITTANCE_RES_Y - 1)
            self._transmittance_lut = self.transmittance(u[None, :] * 2 - 1, v[:, None])
        return self._transmittance_lut

    def lookup_transmittance(self, cos_theta, normalized_altitude):
        lut = self.transmittance_lut
        x = (self.TRANSMITTANCE_RES_X - 1) * np.clip(cos_theta * 0.5 + 0.5, 0.0, 1.0)
        y = (self.TRANSMITTANCE_RES_Y - 1) * np.clip(normalized_altitude, 0.0, 1.0)
        x1, y1 = x.astype(np.int64), y.astype(np.int64)
        x2, y2 = np.minimum(x1 + 1, self.TRANSMITTANCE_RES_X - 1), np.minimum(y1 + 1, self.TRANSMITTANCE_RES_Y - 1)
        fx, fy = (x - x1)[..., None], (y - y1)[..., None]
        bottom = lut[y1, x1] + fx * (lut[y1, x2] - lut[y1, x1])
        top = lut[y2, x1] + fx * (lut[y2, x2] - lut[y2, x1])
        return bottom + fy * (top - bottom)

    def multiple_scattering(self, cos_theta, normalized_altitude, distance):
        """lookup_multiscattering: the fit of the atmosphere's multiple scattering plus the
        ground's second-order bounce, per unit phase, (..., 4)."""
        omega = 2 * math.pi * (1.0 - np.sqrt(np.maximum(1.0 - (self.EARTH_RADIUS / distance) ** 2, 0.0)))
        lut = self.transmittance_lut
        x = (self.TRANSMITTANCE_RES_X - 1) * np.clip(cos_theta * 0.5 + 0.5, 0.0, 1.0)
        x1 = x.astype(np.int64)
        x2 = np.minimum(x1 + 1, self.TRANSMITTANCE_RES_X - 1)
        to_ground = lut[0, x1] + (x - x1)[..., None] * (lut[0, x2] - lut[0, x1])
        column = self.transmittance_lut[:, -1]  # toward the zenith, by altitude
        y = (self.TRANSMITTANCE_RES_Y - 1) * np.clip(normalized_altitude, 0.0, 1.0)
        y1 = y.astype(np.int64)
        y2 = np.minimum(y1 + 1, self.TRANSMITTANCE_RES_Y - 1)
        to_zenith = column[y1] + (y - y1)[..., None] * (column[y2] - column[y1])
        ground_to_sample = column[0] / to_zenith
        ground = (1 / (4 * math.pi)) * omega[..., None] * (self.GROUND_ALBEDO / math.pi) * to_ground * \
            ground_to_sample * cos_theta[..., None]
        fit = self.MULTIPLE_SCATTERING_FIT * (1.0 / (1.0 + 5.0 * np.exp(-17.92 * cos_theta)))[..., None]
        return fit + ground

    def inscattering(self, sun, directions):
        """get_inscattering along `directions` (n, 3) from the camera, to the ground or the
        top of the atmosphere, (n, 4)."""
        origin = np.broadcast_to(np.array([0.0, 0.0, self.EARTH_RADIUS + self.altitude]), directions.shape)
        atmosphere = _ray_sphere_intersection(origin, directions, self.ATMOSPHERE_RADIUS)
        ground = _ray_sphere_intersection(origin, directions, self.EARTH_RADIUS)
        dt = np.where(ground < 0, atmosphere, ground) / self.IN_SCATTERING_STEPS
        cos_theta = -(directions @ sun)
        molecular_phase = 3.0 / 16.0 / math.pi * (1.0 + cos_theta ** 2)
        den = 1.0 + self.G ** 2 + 2.0 * self.G * cos_theta
        aerosol_phase = (1 / (4 * math.pi)) * (1.0 - self.G ** 2) / (den * np.sqrt(den))
        radiance = np.zeros(directions.shape[:-1] + (4,))
        transmittance = np.ones(directions.shape[:-1] + (4,))
        for i in range(self.IN_SCATTERING_STEPS):
            points = origin + directions * ((i + 0.5) * dt)[:, None]
            distance = np.linalg.norm(points, axis=-1)
            altitude = np.maximum(distance - self.EARTH_RADIUS, 0.0)
            normalized_altitude = altitude / self.ATMOSPHERE_THICKNESS
            sample_cos_theta = (points @ sun) / distance
            extinction, molecular, aerosol = self.extinction_and_scattering(altitude)
            to_sun = self.lookup_transmittance(sample_cos_theta, normalized_altitude)
            ms = self.multiple_scattering(sample_cos_theta, normalized_altitude, distance)
            source = self.SUN_SPECTRAL_IRRADIANCE * (molecular * (molecular_phase[:, None] * to_sun + ms) +
                                                     aerosol * (aerosol_phase[:, None] * to_sun + ms))
            step_transmittance = np.exp(-dt[:, None] * extinction)
            radiance += transmittance * (source - source * step_transmittance) / np.maximum(extinction, 1e-7)
            transmittance *= step_transmittance
        return radiance

    def texels(self, rows, columns, sun_elevation):
        """The texture's XYZ at texel (rows, columns): the whole sphere, rows squeezed
        toward the horizon, the sun at azimuth pi."""
        height, width = TEXTURE_SIZE
        azimuth = 2 * math.pi * (columns + 0.5) / width
        level = (rows + 0.5) / height * 2.0 - 1.0
        elevation = np.sign(level) * level ** 2 * math.pi / 2
        directions = np.stack([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                               np.sin(elevation)], axis=-1)
        cos_zenith = math.cos(math.pi / 2 - sun_elevation)
        sun = np.array([-math.sqrt(max(1 - cos_zenith ** 2, 0.0)), 0.0, cos_zenith])
        return self.inscattering(sun, directions) @ self.SPECTRAL_XYZ

    def sun_pixels(self, sun_elevation, angular_diameter):
        """SKY_multiple_scattering_precompute_sun: the disc's XYZ at its lowest and highest
        points, the sun's irradiance through the atmosphere over the disc's solid angle."""
        half = angular_diameter / 2
        solid_angle = 2 * math.pi * (1 - math.cos(half))
        if solid_angle <= 0:
            return np.zeros(3), np.zeros(3)
        cosines = np.cos(math.pi / 2 - np.array([sun_elevation - half, sun_elevation + half]))
        transmittance = self.transmittance(cosines, self.altitude / self.ATMOSPHERE_THICKNESS)
        xyz = (self.SUN_SPECTRAL_IRRADIANCE * transmittance / solid_angle) @ self.SPECTRAL_XYZ
        return xyz[0], xyz[1]


class PreethamSky:
    """The Preetham et al. 1999 sky as Cycles evaluates it (shader_nodes.cpp's
    sky_texture_precompute_preetham, sky.h's sky_radiance_preetham): Perez functions of
    the zenith angle, clamped at the horizon, and of the angle to the sun, in xyY."""

    def __init__(self, sun_direction, turbidity):
        x, y, z = (float(c) for c in sun_direction)
        theta = math.acos(min(max(z, -1.0), 1.0))
        phi = math.atan2(x, y)
        self.sun = np.array([math.sin(theta) * math.sin(phi), math.sin(theta) * math.cos(phi), math.cos(theta)])
        t, t2 = turbidity, turbidity * turbidity
        ts, ts2, ts3 = theta, theta ** 2, theta ** 3
        chi = (4.0 / 9.0 - t / 120.0) * (math.pi - 2.0 * theta)
        zenith = (((4.0453 * t - 4.9710) * math.tan(chi) - 0.2155 * t + 2.4192) * 0.06,
                  (0.00166 * ts3 - 0.00375 * ts2 + 0.00209 * ts) * t2 +
                  (-0.02903 * ts3 + 0.06377 * ts2 - 0.03202 * ts + 0.00394) * t +
                  (0.11693 * ts3 - 0.21196 * ts2 + 0.06052 * ts + 0.25886),
                  (0.00275 * ts3 - 0.00610 * ts2 + 0.00317 * ts) * t2 +
                  (-0.04214 * ts3 + 0.08970 * ts2 - 0.04153 * ts + 0.00516) * t +
                  (0.15346 * ts3 - 0.26756 * ts2 + 0.06670 * ts + 0.26688))
        self.perez = (  # for Y, x, y
            (0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
             -0.0670 * t + 0.3703),
            (-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989,
             -0.0033 * t + 0.0452),
            (-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537,
             -0.0109 * t + 0.0529))
        self.zenith = [value / _perez(c, 0.0, theta) for value, c in zip(zenith, self.perez)]

    def radiance(self, directions):
        """Linear Rec.709 radiance along unit `directions` (..., 3)."""
        d = np.asarray(directions, dtype=np.float64)
        theta = np.minimum(np.arccos(np.clip(d[..., 2], -1.0, 1.0)), math.pi / 2 - 0.001)
        gamma = np.arccos(np.clip(d @ self.sun, -1.0, 1.0))
        big_y, x, y = (zenith * _perez(c, theta, gamma) for zenith, c in zip(self.zenith, self.perez))
        safe_y = np.where(y != 0, y, 1.0)
        big_x = np.where(y != 0, x / safe_y * big_y, 0.0)
        big_z = np.where((y != 0) & (big_y != 0), (1.0 - x - y) / safe_y * big_y, 0.0)
        return xyz_to_rec709(np.stack([big_x, big_y, big_z], axis=-1))


def _perez(c, theta, gamma):
    with np.errstate(over="ignore"):
        return (1.0 + c[0] * np.exp(c[1] / np.cos(theta))) * \
            (1.0 + c[2] * np.exp(c[3] * gamma) + c[4] * np.cos(gamma) ** 2)
