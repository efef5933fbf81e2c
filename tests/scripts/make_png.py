# Write a W x H RGB PNG with the Python standard library only (zlib): a smooth colour ramp
# with a checker, standing in for the face albedo the sfs stage writes in ICT's UV layout.
#   python3 make_png.py OUT.png [W H]
import struct
import sys
import zlib


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def main():
    out = sys.argv[1]
    w = int(sys.argv[2]) if len(sys.argv) > 2 else 256
    h = int(sys.argv[3]) if len(sys.argv) > 3 else 256
    rows = bytearray()
    for y in range(h):
        rows.append(0)  # filter type none
        for x in range(w):
            check = ((x * 8 // w) + (y * 8 // h)) % 2
            rows += bytes((120 + 100 * x // w, 80 + 60 * y // h, 60 + 40 * check))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(rows), 6)) + chunk(b"IEND", b"")
    with open(out, "wb") as f:
        f.write(png)


main()
