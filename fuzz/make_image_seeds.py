#!/usr/bin/env python3
"""Seeds of the image-reader fuzz targets (fuzz/corpus/{texture_png,texture_jpeg,
environment_hdr,image_exr}): a few tiny images of each format and pixel type. Needs Pillow for
PNG and JPEG; HDR and OpenEXR are written by tests/fixtures/bombs/make_bombs.py's writers.

    python3 fuzz/make_image_seeds.py
"""

import os
import sys

from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "fixtures", "bombs"))
import make_bombs  # noqa: E402


def corpus(name):
    path = os.path.join(HERE, "corpus", name)
    os.makedirs(path, exist_ok=True)
    return path


def gradient(mode, w, h):
    img = Image.new("RGBA", (w, h))
    img.putdata([(x * 255 // w, y * 255 // h, 128, 255 - x * 16) for y in range(h) for x in range(w)])
    return img.convert(mode)


def main():
    png = corpus("texture_png")
    gradient("RGB", 4, 3).save(os.path.join(png, "rgb8.png"))
    gradient("RGBA", 3, 3).save(os.path.join(png, "rgba8.png"))
    gradient("L", 5, 2).save(os.path.join(png, "gray8.png"))
    gradient("LA", 2, 2).save(os.path.join(png, "gray-alpha.png"))
    gradient("P", 4, 4).save(os.path.join(png, "palette.png"))
    gradient("I;16", 3, 2).save(os.path.join(png, "gray16.png"))
    gradient("RGB", 8, 8).save(os.path.join(png, "interlaced.png"), interlace=1)
    jpeg = corpus("texture_jpeg")
    gradient("RGB", 16, 8).save(os.path.join(jpeg, "baseline.jpg"), quality=80)
    gradient("RGB", 16, 16).save(os.path.join(jpeg, "progressive.jpg"), progressive=True)
    gradient("L", 8, 8).save(os.path.join(jpeg, "gray.jpg"))
    gradient("RGB", 9, 7).save(os.path.join(jpeg, "subsampled.jpg"), subsampling=2)
    make_bombs.write_hdr(os.path.join(corpus("environment_hdr"), "rle.hdr"), 16, 4)
    make_bombs.write_hdr(os.path.join(corpus("environment_hdr"), "flat.hdr"), 4, 2)
    make_bombs.write_exr(os.path.join(corpus("image_exr"), "zip.exr"), 8, 20)


if __name__ == "__main__":
    main()
