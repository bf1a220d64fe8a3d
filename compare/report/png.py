"""An RGB image as a PNG file, quickly: every row filtered the same way, then deflated.

Pillow (which matplotlib's savefig calls) tries PNG's five row filters on every row of an
image and keeps the best: for the report's figures, mostly white, that search was a fifth of
drawing a figure and made the files 5 % smaller. Here every row is 'Up'-filtered (its
difference to the row above: zero on white, on grid lines, on the flat parts of curves).
"""
from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np

SIGNATURE = b"\x89PNG\r\n\x1a\n"
UP = 2   # PNG filter type 2: each byte minus the byte above it (the row above row 0 is zeros)
# zlib's fastest level: on the built-ins' figures 12 % larger files than its default (6),
# written in half the time
LEVEL = 1


def _chunk(kind: bytes, data: bytes) -> bytes:
    """A PNG chunk: length, type, data, CRC-32 of type and data."""
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def write_rgb(path: str | Path, rgb: np.ndarray) -> None:
    """Write rgb, an (height, width, 3) array of uint8, as the 8-bit RGB PNG path."""
    height, width, _ = rgb.shape
    flat = rgb.reshape(height, 3 * width)
    rows = np.empty((height, 1 + 3 * width), dtype=np.uint8)
    rows[:, 0] = UP
    rows[0, 1:] = flat[0]
    np.subtract(flat[1:], flat[:-1], out=rows[1:, 1:])   # modulo 256, as PNG's filters are
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)   # 8 bits, RGB, no interlace
    Path(path).write_bytes(SIGNATURE + _chunk(b"IHDR", header)
                           + _chunk(b"IDAT", zlib.compress(rows.tobytes(), LEVEL)) + _chunk(b"IEND", b""))
