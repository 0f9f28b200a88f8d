"""Quick previews (--quick): a figure's whole view at low cost. The render
runs at the figure's own size with few samples and also writes its linear
radiance (--pfm); the preview is that image shrunk by a whole factor k, each
k x k block of pixels averaged (which averages their noise too), mapped to
8 bits by the renderer's own curve (common/image_io.cpp) and written as the
figure's PNG. Standard library only."""

import array
import math
import struct
import sys
import zlib


def read_pfm(path):
    """(width, height, pixels) of a colour PFM: pixels an array of floats,
    three per pixel, rows from the bottom (the renderer's order). ValueError
    for anything else."""
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    if len(parts) < 4 or parts[0] != b"PF":
        raise ValueError(f"{path}: not a colour PFM file")
    try:
        width, height = (int(v) for v in parts[1].split())
        scale = float(parts[2])
    except ValueError:
        raise ValueError(f"{path}: bad PFM header")
    if width <= 0 or height <= 0:
        raise ValueError(f"{path}: bad PFM size {width} x {height}")
    pixels = array.array("f")
    body = parts[3]
    if len(body) < width * height * 12:
        raise ValueError(f"{path}: PFM data is truncated")
    pixels.frombytes(body[:width * height * 12])
    if (scale < 0) != (sys.byteorder == "little"):
        pixels.byteswap()
    return width, height, pixels


def shrink(width, height, pixels, k):
    """The image k times smaller each way (the last width % k columns and
    height % k rows dropped), each pixel the mean of its k x k block: rows of
    floats from the top, three per pixel."""
    w2, h2 = width // k, height // k
    row_len = 3 * width
    out = []
    scale = 1.0 / (k * k)
    for j in range(h2):
        # The block's rows, top first; the PFM's rows go from the bottom.
        rows = [pixels[(height - 1 - (j * k + i)) * row_len:(height - j * k - i) * row_len] for i in range(k)]
        summed = [sum(col) for col in zip(*rows)] if k > 1 else list(rows[0])
        channels = []
        for c in range(3):
            parts = [summed[3 * dx + c::3 * k][:w2] for dx in range(k)]
            channels.append([sum(v) * scale for v in zip(*parts)])
        out.append([v for px in zip(*channels) for v in px])
    return w2, h2, out


def radiance_to_byte(L):
    """The renderer's curve: floor(255 (sqrt(2) L)^(1/2.2)), 0 for NaN and
    anything not above 0, 255 at 1 and above."""
    v = math.sqrt(2.0) * L
    if not v > 0.0:
        return 0
    if v == math.inf:
        return 255
    g = v ** (1.0 / 2.2)
    return 255 if g >= 1.0 else int(math.floor(255.0 * g))


def png_bytes(width, height, rows):
    """An 8-bit RGB PNG of rows (top first) of width * 3 bytes each."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)  # filter 0 (none) on every row
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def make_preview(pfm_path, png_path, k):
    """Writes png_path: the PFM shrunk k times and tone-mapped. Returns what
    the preview shows: {"width", "height", "flat": every pixel the same
    colour, "color": the first pixel's bytes}."""
    width, height, pixels = read_pfm(pfm_path)
    k = max(1, min(k, width, height))
    w2, h2, rows = shrink(width, height, pixels, k)
    byte_rows = [[radiance_to_byte(v) for v in row] for row in rows]
    first = tuple(byte_rows[0][:3])
    flat = all(row == list(first) * w2 for row in byte_rows)
    with open(png_path, "wb") as f:
        f.write(png_bytes(w2, h2, byte_rows))
    return {"width": w2, "height": h2, "flat": flat, "color": list(first)}
