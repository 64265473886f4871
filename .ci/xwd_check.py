#!/usr/bin/env python3
"""Checks an X11 screenshot (xwd, 24/32-bit TrueColor) of `kansei app` for a drawn curve.

The canvas is the render module's white background: the rows and columns rich in pure white.
Inside it there must be ink (non-white pixels) and, among them, coloured ones (LAC segments are
coloured by alpha; samples, B-spline and text are grey or black). Exits non-zero otherwise.
"""

import struct
import sys

# The canvas: rows and columns with at least this many white pixels (text, even white text,
# never has that many in one line; the canvas has hundreds).
MIN_WHITE_RUN = 200
# Least ink inside the canvas, pixels: a fitted stroke drawn 2 px wide across a few hundred
# pixels of canvas leaves thousands; the legend and scale bar alone leave a few hundred.
MIN_INK = 1500
# Least coloured pixels: a segment coloured by alpha a few hundred pixels long.
MIN_COLOURED = 200
# The top fraction of the canvas that holds the alpha legend (its ramp is coloured too).
LEGEND_FRACTION = 0.2
# A pixel is coloured when its channels differ by more than this (grey and black do not).
COLOUR_SPREAD = 40


def read_xwd(path):
    data = open(path, "rb").read()
    fields = struct.unpack(">25I", data[:100])
    header_size, _version, _format, depth, width, height = fields[:6]
    byte_order, bits_per_pixel, bytes_per_line = fields[7], fields[11], fields[12]
    red_mask, green_mask, blue_mask = fields[14], fields[15], fields[16]
    ncolors = fields[19]
    if bits_per_pixel != 32:
        sys.exit(f"xwd_check: {bits_per_pixel} bits per pixel, expected 32 (depth {depth})")
    offset = header_size + 12 * ncolors
    endian = "<" if byte_order == 0 else ">"

    def shift(mask):
        return (mask & -mask).bit_length() - 1

    shifts = [shift(m) for m in (red_mask, green_mask, blue_mask)]
    pixels = []
    for y in range(height):
        row = data[offset + y * bytes_per_line : offset + y * bytes_per_line + 4 * width]
        values = struct.unpack(f"{endian}{width}I", row)
        pixels.append([tuple((v >> s) & 255 for s in shifts) for v in values])
    return width, height, pixels


def main():
    width, height, pixels = read_xwd(sys.argv[1])
    is_white = [[p == (255, 255, 255) for p in row] for row in pixels]
    rows = [y for y in range(height) if sum(is_white[y]) >= MIN_WHITE_RUN]
    cols = [x for x in range(width) if sum(is_white[y][x] for y in range(height)) >= MIN_WHITE_RUN]
    if not rows or not cols:
        sys.exit("xwd_check: no white canvas on screen")
    x0, x1, y0, y1 = min(cols), max(cols), min(rows), max(rows)
    ink = coloured = 0
    # The legend's colour ramp sits in the canvas's top right: count colour below it only.
    legend_bottom = y0 + LEGEND_FRACTION * (y1 - y0)
    for y in range(y0, y1 + 1):
        for x in range(x0, x1 + 1):
            r, g, b = pixels[y][x]
            if (r, g, b) != (255, 255, 255):
                ink += 1
                if max(r, g, b) - min(r, g, b) > COLOUR_SPREAD and y > legend_bottom:
                    coloured += 1
    print(f"xwd_check: canvas {x0},{y0}..{x1},{y1}: {ink} ink pixels, {coloured} coloured")
    if ink < MIN_INK or coloured < MIN_COLOURED:
        sys.exit(f"xwd_check: expected at least {MIN_INK} ink and {MIN_COLOURED} coloured pixels")


main()
