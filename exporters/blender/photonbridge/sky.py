"""Blender 3.4's Nishita Sky Texture, baked for photonbridge.

Cycles 3.4 renders ShaderNodeTexSky (sky_type 'NISHITA') in two steps
(intern/sky/source/sky_nishita.cpp, intern/cycles/scene/shader_nodes.cpp,
intern/cycles/kernel/svm/sky.h):

1. a 512 x 128 XYZ texture of the sky above the horizon, single scattering
   (Rayleigh, Mie with g = 0.76, ozone absorption) of the sun's spectrum at
   21 wavelengths 380-780 nm, sampled more densely toward the horizon
   (latitude = (pi/2 + half a row) * (row / 128)^2), with the sun at
   longitude 0 and the texture mirrored about it;
2. a lookup per ray: above the horizon the texture (bilinear, clamped at the
   edges) at x = (phi + pi + rotation) / 2pi, y = sqrt(elevation / (pi/2)),
   phi = atan2(dir.x, dir.y); below it the horizon row fading as
   (1 + 2.5 z)^3 to black at z = -0.4; the sun disc (when on) from two
   precomputed pixels (the sun's transmitted spectrum at the disc's bottom
   and top elevation, divided by its solid angle) with limb darkening
   1 - 0.6 (1 - sqrt(1 - (angle / half angle)^2)); XYZ -> linear Rec.709,
   negative components clamped to 0 (measured: a sun at the horizon gives
   negative blue, which Cycles 3.4 renders as 0).

This module does the same in numpy and bakes step 2 into an equirectangular
map in photonbridge's layout (world.c: u = 0.5 - atan2(y, x) / 2pi,
v = acos(z) / pi, row 0 at the zenith). The sun disc is not baked: it is
0.545 degrees wide and ~1e6 times brighter than the sky, so a texel map
would need ~0.05 degree texels to hold it and the sampling table would still
see a single hot texel; instead sun_irradiance() integrates the disc exactly
as the kernel shades it (horizon cut included) and the writer emits it as
the extension's soft sun of angle sun_size, which photonbridge samples
directly.
"""

import math

import numpy as np

# ---- sky_nishita.cpp constants (physical data) -------------------------------
RAYLEIGH_SCALE = 8e3
MIE_SCALE = 1.2e3
MIE_COEFF = 2e-5
MIE_G = 0.76
EARTH_RADIUS = 6360e3
ATMOSPHERE_RADIUS = 6420e3
STEPS = 32
STEP_LAMBDA = (780 - 380) / 20.0
# Solar irradiance at the top of the atmosphere, W m^-2 nm^-1, 380..780 nm.
IRRADIANCE = np.array([
    1.45756829855592995315, 1.56596305559738380175, 1.65148449067670455293,
    1.71496242737209314555, 1.75797983805020541226, 1.78256407885924539336,
    1.79095108475838560302, 1.78541550133410664714, 1.76815554864306845317,
    1.74122069647250410362, 1.70647127164943679389, 1.66556087452739887134,
    1.61993437242451854274, 1.57083597368892080581, 1.51932335059305478886,
    1.46628494965214395407, 1.41245852740172450623, 1.35844961970384092709,
    1.30474913844739281998, 1.25174963272610817455, 1.19975998755420620867])
# Rayleigh scattering coefficient, m^-1.
RAYLEIGH_COEFF = np.array([
    5.424820087636473e-05, 4.418549866505454e-05, 3.635151910165377e-05,
    3.017929012024763e-05, 2.526320226989157e-05, 2.130859310621843e-05,
    1.809838025320633e-05, 1.547057129129042e-05, 1.330284977336850e-05,
    1.150184784075764e-05, 9.99557429990163e-06, 8.72799973630707e-06,
    7.65513700977967e-06, 6.74217203751443e-06, 5.96134125832052e-06,
    5.29034598065810e-06, 4.71115687557433e-06, 4.20910481110487e-06,
    3.77218381260133e-06, 3.39051255477280e-06, 3.05591531679811e-06])
# Ozone absorption coefficient, m^-1.
OZONE_COEFF = np.array([
    3.25126849861e-09, 5.85395365047e-09, 1.977191155085e-08,
    7.309568762914e-08, 2.0084561514287e-07, 4.0383958096161e-07,
    6.3551335912363e-07, 9.6707041180970e-07, 1.54797400424410e-06,
    2.09038647223331e-06, 2.46128056164565e-06, 2.73551299461512e-06,
    2.15125863128643e-06, 1.59051840791988e-06, 1.12356197979857e-06,
    7.3527551487574e-07, 4.6450130357806e-07, 3.3096079921048e-07,
    2.2512612292678e-07, 1.4879129266490e-07, 1.6828623364192e-07])
# CIE 1931 2-degree colour matching functions at the 21 wavelengths.
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
# 8-node Gauss-Laguerre quadrature for the optical depth toward the sun,
# nodes scaled to the ray length, weights with exp(x) folded in.
QUAD_NODES = np.array([0.006811185292, 0.03614807107, 0.09004346519, 0.1706680068,
                       0.2818362161, 0.4303406404, 0.6296271457, 0.9145252695])
QUAD_WEIGHTS = np.array([0.01750893642, 0.04135477391, 0.06678839063, 0.09507698807,
                         0.1283416365, 0.1707430204, 0.2327233347, 0.3562490486])
# CIE XYZ (D65) -> linear Rec.709, Blender 3.4's scene-linear colour space.
XYZ_TO_REC709 = np.array([[3.2404542, -1.5371385, -0.4985314],
                          [-0.9692660, 1.8760108, 0.0415560],
                          [0.0556434, -0.2040259, 1.0572252]])

TEX_W, TEX_H = 512, 128  # Cycles' sky texture


def _geo_dir(lat, lon):
    lat, lon = np.broadcast_arrays(np.asarray(lat, np.float64), np.asarray(lon, np.float64))
    return np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], -1)


def _atmosphere_distance(pos, d):
    """Distance from pos along unit d to the atmosphere's outer sphere."""
    b = 2.0 * np.sum(d * pos, -1)
    c = np.sum(pos * pos, -1) - ATMOSPHERE_RADIUS ** 2
    return (-b + np.sqrt(np.maximum(b * b - 4.0 * c, 0.0))) / 2.0


def _densities(height):
    """Rayleigh, Mie and ozone density factors at height (m), (..., 3)."""
    oz = np.where((height >= 10000) & (height < 25000), height / 15000.0 - 2.0 / 3.0,
                  np.where((height >= 25000) & (height < 40000), -(height / 15000.0 - 8.0 / 3.0), 0.0))
    return np.stack([np.exp(-height / RAYLEIGH_SCALE), np.exp(-height / MIE_SCALE), oz], -1)


def _optical_depth(pos, d):
    """Optical depth factors (Rayleigh, Mie, ozone) from pos along d (..., 3)."""
    length = _atmosphere_distance(pos, d)
    acc = 0.0
    for x, w in zip(QUAD_NODES, QUAD_WEIGHTS):
        p = pos + (x * length)[..., None] * d
        acc = acc + _densities(np.linalg.norm(p, axis=-1) - EARTH_RADIUS) * w
    return acc * length[..., None]


def _phases(mu):
    g2 = MIE_G * MIE_G
    ray = 3.0 / (16.0 * math.pi) * (1.0 + mu * mu)
    mie = (3.0 * (1.0 - g2) * (1.0 + mu * mu)) / (
        8.0 * math.pi * (2.0 + g2) * np.power(1.0 + g2 - 2.0 * MIE_G * mu, 1.5))
    return ray, mie


def _spec_to_xyz(spec):
    return (spec @ CMF_XYZ) * STEP_LAMBDA


def precompute_texture(sun_elevation, altitude, air, dust, ozone):
    """Cycles' sky texture: (TEX_H, TEX_W, 3) XYZ, row y at latitude
    (pi/2 + half row) (y / H)^2, column x at longitude 2pi x / W - pi."""
    half = TEX_W // 2
    lat_step = math.pi / 2 / TEX_H
    rows = np.arange(TEX_H)
    lat = (math.pi / 2 + lat_step / 2) * (rows / TEX_H) ** 2
    lon = 2 * math.pi / TEX_W * np.arange(half) - math.pi
    dirs = _geo_dir(lat[:, None], lon[None, :]).reshape(-1, 3)  # (N, 3)
    cam = np.array([0.0, 0.0, EARTH_RADIUS + altitude])
    sun = _geo_dir(sun_elevation, 0.0)
    scale = np.array([air, dust, ozone])
    n = len(dirs)
    seg = _atmosphere_distance(np.broadcast_to(cam, dirs.shape), dirs) / STEPS  # (N,)
    ray_ph, mie_ph = _phases(dirs @ sun)
    spec = np.zeros((n, 21))
    depth = np.zeros((n, 3))
    ext = np.stack([RAYLEIGH_COEFF, np.full(21, 1.11 * MIE_COEFF), OZONE_COEFF], 0)  # (3, 21)
    for i in range(STEPS):
        p = cam + ((i + 0.5) * seg)[:, None] * dirs
        dens = scale * _densities(np.linalg.norm(p, axis=-1) - EARTH_RADIUS)
        depth = depth + seg[:, None] * dens
        # Is the Earth in the way toward the sun? (sun below this point's horizon)
        b = 2.0 * (p @ sun)
        c = np.sum(p * p, -1) - EARTH_RADIUS ** 2
        lit = ~((sun[2] < 0) & (b * b - 4.0 * c >= 0.0))
        light = scale * _optical_depth(p, np.broadcast_to(sun, p.shape))
        att = np.exp(-((depth + light) @ ext))  # (N, 21)
        scat = dens[:, 0:1] * RAYLEIGH_COEFF * ray_ph[:, None] + dens[:, 1:2] * MIE_COEFF * mie_ph[:, None]
        spec += np.where(lit[:, None], att * scat * IRRADIANCE * seg[:, None], 0.0)
    xyz = _spec_to_xyz(spec).reshape(TEX_H, half, 3)
    return np.concatenate([xyz, xyz[:, ::-1]], 1)


def precompute_sun(sun_elevation, angular_diameter, altitude, air, dust):
    """The sun disc's bottom and top XYZ radiance (sun_radiation: no ozone)."""
    half = angular_diameter / 2.0
    solid = 2 * math.pi * (1.0 - math.cos(half))
    cam = np.array([0.0, 0.0, EARTH_RADIUS + altitude])
    out = []
    for e in (max(sun_elevation - half, 0.0), max(sun_elevation + half, 0.0)):
        d = _geo_dir(e, 0.0)
        od = _optical_depth(cam, d)
        tau = RAYLEIGH_COEFF * od[0] * air + 1.11 * MIE_COEFF * od[1] * dust
        out.append(_spec_to_xyz(IRRADIANCE * np.exp(-tau) / solid))
    return out[0], out[1]


def _tex_lookup(tex, x, y):
    """kernel_tex_image_interp, linear, extension EXTEND (clamped)."""
    h, w = tex.shape[:2]
    fx, fy = x * w - 0.5, y * h - 0.5
    x0, y0 = np.floor(fx), np.floor(fy)
    ax, ay = (fx - x0)[..., None], (fy - y0)[..., None]
    x0, y0 = x0.astype(np.int64), y0.astype(np.int64)
    xa, xb = np.clip(x0, 0, w - 1), np.clip(x0 + 1, 0, w - 1)
    ya, yb = np.clip(y0, 0, h - 1), np.clip(y0 + 1, 0, h - 1)
    return ((tex[ya, xa] * (1 - ax) + tex[ya, xb] * ax) * (1 - ay) +
            (tex[yb, xa] * (1 - ax) + tex[yb, xb] * ax) * ay)


def _dust(node):
    """Dust density: 'Aerosol' (aerosol_density) from Blender 5.0 on."""
    v = getattr(node, "dust_density", None)
    return float(v if v is not None else node.aerosol_density)


class NishitaSky:
    """The node's parameters as Cycles 3.4's SkyTextureNode::compile uses them."""

    def __init__(self, node):
        self.sun_elevation = float(node.sun_elevation)
        rot = math.fmod(float(node.sun_rotation), 2 * math.pi)
        if rot < 0:
            rot += 2 * math.pi
        self.sun_rotation = 2 * math.pi - rot  # shader_nodes.cpp flips it
        self.altitude = min(max(float(node.altitude), 1.0), 59999.0)
        self.air, self.dust, self.ozone = float(node.air_density), float(_dust(node)), float(node.ozone_density)
        self.sun_disc = bool(node.sun_disc)
        self.sun_size = float(node.sun_size)
        self.sun_intensity = float(node.sun_intensity)
        self.tex = precompute_texture(self.sun_elevation, self.altitude, self.air, self.dust, self.ozone)

    def sun_direction(self):
        """Unit vector toward the sun's centre, Blender axes (Z up)."""
        return _geo_dir(self.sun_elevation, self.sun_rotation + math.pi / 2)

    def sky_xyz(self, d):
        """The kernel's radiance (XYZ) toward unit directions d (..., 3), sun disc left out."""
        theta = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        phi = np.arctan2(d[..., 0], d[..., 1])
        x = (phi + math.pi + self.sun_rotation) / (2 * math.pi)
        x = np.where(x > 1.0, x - 1.0, x)
        elev = math.pi / 2 - theta
        up = d[..., 2] >= 0.0
        y = np.where(up, np.sqrt(np.maximum(elev, 0.0) / (math.pi / 2)), -0.5)
        xyz = _tex_lookup(self.tex, x, y)
        fade = (1.0 + d[..., 2] * 2.5) ** 3
        fade = np.where(up, 1.0, np.where(d[..., 2] < -0.4, 0.0, fade))
        return xyz * fade[..., None]

    def bake(self, width=1024, height=512):
        """Linear Rec.709 radiance, (height, width, 3) float32, photonbridge's
        equirectangular layout (row 0 at the zenith), each texel the mean of
        2 x 2 kernel lookups."""
        acc = np.zeros((height, width, 3))
        for sy in (0.25, 0.75):
            for sx in (0.25, 0.75):
                u = (np.arange(width) + sx) / width
                v = (np.arange(height) + sy) / height
                phi = math.pi * (1.0 - 2.0 * u)[None, :]
                th = (math.pi * v)[:, None]
                d = np.stack(np.broadcast_arrays(np.sin(th) * np.cos(phi), np.sin(th) * np.sin(phi),
                                                 np.cos(th)), -1)
                acc += np.maximum(self.sky_xyz(d) @ XYZ_TO_REC709.T, 0.0)  # Cycles clamps each lookup
        return (acc / 4.0).astype(np.float32)

    def sun_irradiance(self, n=96):
        """Linear Rec.709 irradiance (W/m^2 per channel, normal to the sun) of
        the disc as the kernel shades it: bottom/top interpolation, limb
        darkening, the part below the horizon cut; None when the disc is off."""
        if not self.sun_disc or not self.sun_size > 0:
            return None
        half = self.sun_size / 2.0
        bottom, top = precompute_sun(self.sun_elevation, self.sun_size, self.altitude, self.air, self.dust)
        # Polar grid over the disc in the sun's tangent plane (small angles).
        r = (np.arange(n) + 0.5) / n * half
        a = (np.arange(4 * n) + 0.5) / (4 * n) * 2 * math.pi
        rr, aa = np.meshgrid(r, a, indexing="ij")
        dw = (half / n) * (2 * math.pi / (4 * n)) * np.sin(rr)  # solid angle of each cell
        elev = self.sun_elevation + rr * np.sin(aa)  # elevation offset across the disc
        e0 = self.sun_elevation
        if e0 - half > 0.0:
            y = (elev - e0) / self.sun_size + 0.5
        else:
            y = elev / (e0 + half) if e0 + half > 0.0 else np.zeros_like(elev)
        xyz = bottom + y[..., None] * (top - bottom)
        xyz = xyz * self.sun_intensity * (1.0 - 0.6 * (1.0 - np.sqrt(1.0 - (rr / half) ** 2)))[..., None]
        if not e0 + half > 0.0:
            xyz = xyz * 0.0
        xyz = xyz * (elev >= 0.0)[..., None]
        rgb = np.maximum(xyz @ XYZ_TO_REC709.T, 0.0)  # clamped as each lookup
        return np.sum(rgb * dw[..., None], (0, 1))


_last = {}


def baked(node):
    """(NishitaSky, baked map, sun irradiance or None) of a Sky Texture
    node; the last result is kept, so a viewport re-export of an unchanged
    sky does not bake it again (~4 s)."""
    key = tuple(float(getattr(node, k)) for k in ("sun_elevation", "sun_rotation", "altitude", "air_density",
                                                   "ozone_density", "sun_size", "sun_intensity")) + (_dust(node),)
    key += (bool(node.sun_disc),)
    if _last.get("key") != key:
        sky = NishitaSky(node)
        _last.clear()
        _last.update(key=key, value=(sky, sky.bake(), sky.sun_irradiance()))
    return _last["value"]


def write_hdr(path, rgb):
    """Radiance RGBE (.hdr), flat scanlines, row 0 first (top)."""
    h, w = rgb.shape[:2]
    v = np.maximum(rgb.astype(np.float64), 0.0)
    m = v.max(-1)
    mant, ex = np.frexp(m)
    scale = np.where(m > 1e-32, mant * 256.0 / np.maximum(m, 1e-300), 0.0)
    rgbe = np.zeros((h, w, 4), np.uint8)
    rgbe[..., :3] = np.clip(np.floor(v * scale[..., None] + 0.5), 0, 255).astype(np.uint8)
    rgbe[..., 3] = np.where(m > 1e-32, ex + 128, 0).astype(np.uint8)
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        f.write(rgbe.tobytes())
