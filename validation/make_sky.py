#!/usr/bin/env python3
"""Write the procedural sky environment map: scenes/assets/sky.exr and its copy
validation/env-spheres/sky.exr (the validation scenes read files beside themselves).

    pip install mitsuba numpy
    python validation/make_sky.py

A latitude-longitude (equirectangular) linear-RGB float32 OpenEXR image, 256 x 128: a blue
sky getting lighter toward the horizon, a dim brown ground below it (radiance about 0.12), and a
soft sun at 35 degrees elevation: a disk of radiance about 32 (60 times the sky's mean, 0.55) 5 degrees
in radius, fading out by 8 degrees, so that sampling the map by its luminance matters, but not a
delta. The sun gives about 30% of the irradiance on the ground, the sky the rest.

Mapping (Mitsuba 3's `envmap`, checked on 3.9.1 by evaluating the emitter, see README.md):
+y is up; a direction d has u = atan2(d.x, -d.z) / 2 pi (wrapped into [0, 1)) and
v = acos(d.y) / pi; row 0 is the top (+y). Mitsuba interpolates bilinearly between texels
placed at u = (i + 0.5) / W horizontally (wrapping around) but at v = j / (H - 1) vertically
(row 0 exactly at the zenith, the last row at the nadir), so each texel here holds the sky
evaluated in the direction Mitsuba gives it.

Only numpy and Mitsuba's Bitmap (to write the EXR) are needed.
"""

import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
OUTPUTS = [os.path.join(ROOT, "scenes", "assets", "sky.exr"), os.path.join(HERE, "env-spheres", "sky.exr")]

WIDTH, HEIGHT = 256, 128
ZENITH = np.array([0.20, 0.36, 0.85])
HORIZON = np.array([0.80, 0.88, 1.00])
GROUND = np.array([0.20, 0.15, 0.10])
SUN = np.array([34.0, 31.5, 27.0])  # radiance of the sun's disk
SUN_CORE, SUN_EDGE = np.radians(5.0), np.radians(8.0)  # full radiance to SUN_CORE, none beyond SUN_EDGE
SUN_ELEVATION = np.radians(35.0)
SUN_U = 0.35  # azimuth as the map's u: toward +x and +z (right of and behind a camera looking down -z)
GLOW = 0.6  # aureole: GLOW * SUN / max(SUN) * exp(-a / 10 degrees), about doubling the sky near the sun


def direction(u, v):
    """Mitsuba's envmap: the direction of map coordinates (u, v)."""
    theta, phi = np.pi * v, 2 * np.pi * u
    return np.stack([np.sin(phi) * np.sin(theta), np.cos(theta), -np.cos(phi) * np.sin(theta)], axis=-1)


def smoothstep(a, b, x):
    t = np.clip((x - a) / (b - a), 0.0, 1.0)
    return t * t * (3 - 2 * t)


def sky(d):
    y = d[..., 1:2]
    up = np.sqrt(np.clip(y, 0.0, 1.0))
    air = HORIZON * (1 - up) + ZENITH * up
    # The ground: dim brown, a little darker straight down; 2 degrees of blend at the horizon.
    ground = GROUND * (1.0 + 0.25 * np.clip(y, -1.0, 0.0))
    above = smoothstep(-0.02, 0.02, y)
    c = air * above + ground * (1 - above)
    sun_d = direction(SUN_U, 0.5 - SUN_ELEVATION / np.pi)
    a = np.arccos(np.clip(d @ sun_d, -1.0, 1.0))[..., None]
    core = 1 - smoothstep(SUN_CORE, SUN_EDGE, a)
    glow = GLOW * np.exp(-a / np.radians(10.0)) * above
    return c + SUN * core + (SUN / SUN.max()) * glow


def make():
    u = (np.arange(WIDTH) + 0.5) / WIDTH
    v = np.arange(HEIGHT) / (HEIGHT - 1)
    uu, vv = np.meshgrid(u, v)
    return sky(direction(uu, vv)).astype(np.float32)


def main():
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    img = make()
    for out in OUTPUTS:
        os.makedirs(os.path.dirname(out), exist_ok=True)
        mi.Bitmap(img, pixel_format=mi.Bitmap.PixelFormat.RGB).write(out)
        print(f"wrote {os.path.relpath(out)} ({os.path.getsize(out) // 1024} KB)")
    # Texel j stands for the band around theta = pi j / (H - 1) (Mitsuba's rows, see above).
    lum = img.astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    theta = np.pi * np.arange(HEIGHT) / (HEIGHT - 1)
    d_omega = np.broadcast_to(np.sin(theta)[:, None] * (np.pi / (HEIGHT - 1)) * (2 * np.pi / WIDTH), lum.shape)
    cos = np.broadcast_to(np.cos(theta)[:, None], lum.shape)
    up, sun = cos > 0, lum > 5.0
    e = (lum * cos * d_omega)[up].sum()
    print(
        f"peak luminance {lum.max():.1f}; sky (upper half without the sun) mean "
        f"{(lum * d_omega)[up & ~sun].sum() / d_omega[up & ~sun].sum():.3f}; ground {lum[-HEIGHT // 4:].mean():.3f}; "
        f"sun {d_omega[sun].sum():.4f} sr, {(lum * cos * d_omega)[up & sun].sum() / e:.0%} of the irradiance "
        f"{e:.2f} on a horizontal plane"
    )

if __name__ == "__main__":
    main()
