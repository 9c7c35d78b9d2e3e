#!/usr/bin/python3
"""Converts an X window dump (xwd -root of a TrueColor screen, 24 or 32 bits per pixel) to PNG
with Pillow: scripts/tools/ros_screenshot.sh's capture without ImageMagick.

usage: xwd_to_png.py IN.xwd OUT.png
"""
import struct
import sys

from PIL import Image


def main():
    data = open(sys.argv[1], "rb").read()
    h = struct.unpack(">25I", data[:100])
    header_size, version, fmt, depth, width, height = h[0], h[1], h[2], h[3], h[4], h[5]
    byte_order, bits_per_pixel, bytes_per_line, ncolors = h[7], h[11], h[12], h[19]
    if version != 7 or fmt != 2 or bits_per_pixel not in (24, 32):
        sys.exit("xwd_to_png: only ZPixmap dumps of 24 or 32 bits per pixel (version 7), got version %d format %d bpp %d"
                 % (version, fmt, bits_per_pixel))
    offset = header_size + 12 * ncolors
    raw = data[offset:offset + bytes_per_line * height]
    if bits_per_pixel == 32:
        mode = "BGRX" if byte_order == 0 else "XRGB"
    else:
        mode = "BGR" if byte_order == 0 else "RGB"
    Image.frombuffer("RGB", (width, height), raw, "raw", mode, bytes_per_line, 1).save(sys.argv[2])


if __name__ == "__main__":
    main()
