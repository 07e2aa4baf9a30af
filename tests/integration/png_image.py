"""Reads the 8-bit RGBA PNGs hapsim-viewer writes (stb_image_write) without
Pillow, and projects world points with the viewer's camera written out
independently (orbit camera: eye at target - distance * forward, pinhole)."""
import math
import struct
import zlib


def read_png(path):
    """(width, height, rows) with rows[y][4*x + c], row 0 the top one."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, idat = 8, b""
    width = height = None
    while pos < len(data):
        n = struct.unpack(">I", data[pos:pos + 4])[0]
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour == 6 and interlace == 0, f"{path}: not 8-bit RGBA"
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    raw = zlib.decompress(idat)
    stride, bpp = 4 * width, 4
    rows, prev, i = [], bytearray(stride), 0
    for _ in range(height):
        f = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        if f == 1:
            for x in range(bpp, stride):
                line[x] = (line[x] + line[x - bpp]) & 255
        elif f == 2:
            for x in range(stride):
                line[x] = (line[x] + prev[x]) & 255
        elif f == 3:
            for x in range(stride):
                a = line[x - bpp] if x >= bpp else 0
                line[x] = (line[x] + ((a + prev[x]) >> 1)) & 255
        elif f == 4:
            for x in range(stride):
                a = line[x - bpp] if x >= bpp else 0
                b = prev[x]
                c = prev[x - bpp] if x >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, rows


def pixel(image, x, y):
    _, _, rows = image
    row = rows[int(y)]
    return tuple(row[4 * int(x):4 * int(x) + 3])


def project(point, target, distance, yaw_deg, pitch_deg, fov_deg, width, height):
    """Pixel (x right, y down) of a world point for the viewer's --camera."""
    yaw, pitch = math.radians(yaw_deg), math.radians(pitch_deg)
    forward = (math.sin(yaw) * math.cos(pitch), math.cos(yaw) * math.cos(pitch), -math.sin(pitch))
    eye = tuple(t - distance * f for t, f in zip(target, forward))
    right = (forward[1], -forward[0], 0.0)  # forward x (0, 0, 1)
    norm = math.hypot(right[0], right[1])
    right = (right[0] / norm, right[1] / norm, 0.0)
    up = (right[1] * forward[2] - right[2] * forward[1], right[2] * forward[0] - right[0] * forward[2],
          right[0] * forward[1] - right[1] * forward[0])
    d = tuple(p - e for p, e in zip(point, eye))
    depth = sum(a * b for a, b in zip(d, forward))
    a = sum(x * y for x, y in zip(d, right))
    b = sum(x * y for x, y in zip(d, up))
    focal = (height / 2) / math.tan(math.radians(fov_deg) / 2)
    return width / 2 + a / depth * focal, height / 2 - b / depth * focal


def patch_difference(first, second, cx, cy, half):
    """Mean |difference| per channel over a (2 half + 1)^2 patch."""
    total, n = 0, 0
    for y in range(int(cy) - half, int(cy) + half + 1):
        for x in range(int(cx) - half, int(cx) + half + 1):
            p, q = pixel(first, x, y), pixel(second, x, y)
            total += sum(abs(u - v) for u, v in zip(p, q))
            n += 3
    return total / n
