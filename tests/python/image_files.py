"""Small image files of every format gmonrt reads, valid and malformed,
built from bytes (shared by tests/python/test_image_inputs.py and
tests/fuzz/make_image_seeds.py). Valid images are one colour, COLOUR (8-bit
sRGB) or LINEAR (linear floats), so that whatever part of the image a
render sees, it sees that colour; R, G and B differ so that a swapped
channel order shows."""

import struct
import zlib

import numpy as np

COLOUR = (200, 120, 40)
LINEAR = (0.75, 0.5, 0.25)  # exact in RGBE, half and float
SIDE = 8


def srgb_to_linear(v):
    v = v / 255.0
    return v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4


# --- PNG ---


def png_chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def png(width=SIDE, height=SIDE, colour=COLOUR, ihdr_size=None, chunks_before=b""):
    w, h = ihdr_size or (width, height)
    rows = b"".join(b"\0" + bytes(colour) * width for _ in range(height))
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) + chunks_before +
            png_chunk(b"IDAT", zlib.compress(rows)) + png_chunk(b"IEND", b""))


def png_palette(width=SIDE, height=SIDE, index=0, entries=1):
    rows = b"".join(b"\0" + bytes([index]) * width for _ in range(height))
    palette = bytes(COLOUR) * entries
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 3, 0, 0, 0)) +
            png_chunk(b"PLTE", palette) + png_chunk(b"IDAT", zlib.compress(rows)) + png_chunk(b"IEND", b""))


def png_interlaced_palette(width=13, height=13, index=1, depth=4):
    """Adam7-interlaced, `depth`-bit palette indices (colour 1 is COLOUR):
    each pass's first row unfiltered, the others filtered Up (all zero
    differences), which the palette index check must undo."""
    passes = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]
    raw = b""
    for x0, y0, dx, dy in passes:
        pass_width = (width - x0 + dx - 1) // dx if width > x0 else 0
        pass_height = (height - y0 + dy - 1) // dy if height > y0 else 0
        bits = format(index, f"0{depth}b") * pass_width
        bits += "0" * ((-len(bits)) % 8)
        row = bytes(int(bits[i:i + 8], 2) for i in range(0, len(bits), 8))
        for y in range(pass_height if pass_width else 0):
            raw += b"\0" + row if y == 0 else b"\2" + bytes(len(row))
    ihdr = struct.pack(">IIBBBBB", width, height, depth, 3, 0, 0, 1)
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + png_chunk(b"PLTE", b"\0\0\0" + bytes(COLOUR)) +
            png_chunk(b"IDAT", zlib.compress(raw)) + png_chunk(b"IEND", b""))


def png_odd_chunk(kind):
    """A valid PNG with an extra (critical) chunk of type `kind`, which may
    hold control bytes; its CRC is right."""
    return png(chunks_before=png_chunk(kind, b"x"))


# --- TGA ---


def tga(width=SIDE, height=SIDE, colour=COLOUR, rle=False, header_only=False):
    header = struct.pack("<BBBHHBHHHHBB", 0, 0, 10 if rle else 2, 0, 0, 0, 0, 0, width, height, 24, 0)
    if header_only:
        return header
    bgr = bytes(reversed(colour))
    if not rle:
        return header + bgr * (width * height)
    packets = b""
    left = width * height
    while left:
        n = min(left, 128)
        packets += bytes([0x80 | (n - 1)]) + bgr
        left -= n
    return header + packets


# --- BMP ---


def bmp(width=SIDE, height=SIDE, colour=COLOUR, header_only=False):
    row = bytes(reversed(colour)) * width
    row += b"\0" * ((-len(row)) % 4)
    pixels = b"" if header_only else row * height
    info = struct.pack("<IiiHHIIiiII", 40, width, height, 1, 24, 0, len(row) * height, 2835, 2835, 0, 0)
    return b"BM" + struct.pack("<IHHI", 54 + len(pixels), 0, 0, 54) + info + pixels


def bmp_palette(width=SIDE, height=SIDE, index=3, entries=2):
    """8-bit with `entries` palette colours, every pixel colour `index`."""
    row = bytes([index]) * width + b"\0" * ((-width) % 4)
    palette = (bytes(reversed(COLOUR)) + b"\0") * entries
    offset = 54 + len(palette)
    info = struct.pack("<IiiHHIIiiII", 40, width, height, 1, 8, 0, len(row) * height, 2835, 2835, entries, 0)
    return b"BM" + struct.pack("<IHHI", offset + len(row) * height, 0, 0, offset) + info + palette + row * height


# --- Radiance HDR ---

RGBE = bytes([192, 128, 64, 128])  # LINEAR


def hdr(width=SIDE, height=SIDE, rle=True, header_size=None):
    w, h = header_size or (width, height)
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + b"-Y %d +X %d\n" % (h, w)
    if header_size:
        return head
    if not rle:
        return head + RGBE * (width * height)
    line = bytes([2, 2, width >> 8, width & 255])
    for value in RGBE:
        left = width
        while left:
            n = min(left, 127)
            line += bytes([128 + n, value])
            left -= n
    return head + line * height


# --- JPEG: a baseline greyscale encoder for one-colour images ---


JPEG_GREY = 200  # its DC difference, 72, is one of category 7


def jpeg(width=SIDE, height=SIDE, grey=JPEG_GREY, header_size=None, scan_bytes=None):
    """Every 8x8 block has the same DC coefficient and no AC ones. The DC
    table codes category 0 as '0' and category 7 as '10'; the AC table codes
    end-of-block as '0'; quantisation is 8 for DC."""
    w, h = header_size or (width, height)
    dc = (grey - 128) * 8 // 8  # level-shifted mean times 8, over the quantiser 8
    assert 64 <= abs(dc) <= 127 or dc == 0
    bits = ""
    blocks = ((width + 7) // 8) * ((height + 7) // 8)
    for b in range(blocks):
        if b == 0 and dc != 0:
            magnitude = dc if dc > 0 else dc + 127
            bits += "10" + format(magnitude, "07b")
        else:
            bits += "0"
        bits += "0"  # end of block
    bits += "1" * ((-len(bits)) % 8)
    data = bytearray()
    for i in range(0, len(bits), 8):
        byte = int(bits[i:i + 8], 2)
        data.append(byte)
        if byte == 0xFF:
            data.append(0)
    if scan_bytes is not None:
        data = bytes(scan_bytes)

    def segment(marker, body):
        return bytes([0xFF, marker]) + struct.pack(">H", len(body) + 2) + body

    quant = bytes([0]) + bytes([8] + [1] * 63)
    dc_table = bytes([0x00]) + bytes([1, 1] + [0] * 14) + bytes([0, 7])
    ac_table = bytes([0x10]) + bytes([1] + [0] * 15) + bytes([0])
    frame = struct.pack(">BHHB", 8, h, w, 1) + bytes([1, 0x11, 0])
    scan = bytes([1, 1, 0x00, 0, 63, 0])
    return (b"\xFF\xD8" + segment(0xDB, quant) + segment(0xC0, frame) + segment(0xC4, dc_table) +
            segment(0xC4, ac_table) + segment(0xDA, scan) + bytes(data) + b"\xFF\xD9")



# --- GIF: one colour, LZW by hand (clear, index 0 repeated, end) ---


def gif(width=SIDE, height=SIDE, screen=None):
    sw, sh = screen or (width, height)
    table = bytes(COLOUR) + b"\0\0\0"  # 2 colours
    # Minimum code size 2: clear = 4, end = 5, codes of 3 bits. Every texel
    # is a literal 0, and a clear before each keeps codes at 3 bits.
    codes = []
    for _ in range(width * height):
        codes += [4, 0]
    codes.append(5)
    bits = "".join(format(c, "03b")[::-1] for c in codes)
    bits += "0" * ((-len(bits)) % 8)
    lzw = bytes(int(bits[i:i + 8][::-1], 2) for i in range(0, len(bits), 8))
    blocks = b"".join(bytes([len(lzw[i:i + 255])]) + lzw[i:i + 255] for i in range(0, len(lzw), 255)) + b"\0"
    return (b"GIF89a" + struct.pack("<HHBBB", sw, sh, 0x80, 0, 0) + table + b"\x2C" +
            struct.pack("<HHHHB", 0, 0, width, height, 0) + b"\x02" + blocks + b"\x3B")


# --- PSD: RGB, 8-bit, raw ---


def psd(width=SIDE, height=SIDE, header_size=None):
    w, h = header_size or (width, height)
    head = b"8BPS" + struct.pack(">H6xHIIHH", 1, 3, h, w, 8, 3) + b"\0" * 12 + struct.pack(">H", 0)
    if header_size:
        return head
    return head + b"".join(bytes([c]) * (width * height) for c in COLOUR)


# --- PNM ---


def ppm(width=SIDE, height=SIDE, header_size=None):
    w, h = header_size or (width, height)
    head = b"P6\n# gmonrt test\n%d %d\n255\n" % (w, h)
    return head if header_size else head + bytes(COLOUR) * (width * height)


def pgm16(width=SIDE, height=SIDE):
    return b"P5\n%d %d\n65535\n" % (width, height) + struct.pack(">H", COLOUR[1] * 257) * (width * height)


# --- Softimage PIC: one uncompressed RGB packet ---


def pic(width=SIDE, height=SIDE, header_size=None):
    w, h = header_size or (width, height)
    head = b"\x53\x80\xF6\x34" + b"\0" * 84 + b"PICT" + struct.pack(">HHfHH", w, h, 1.0, 3, 0)
    head += bytes([0, 8, 0, 0xE0])
    return head if header_size else head + bytes(COLOUR) * (width * height)


# --- PFM and EXR (linear) ---


def pfm(width=SIDE, height=SIDE):
    return b"PF\n%d %d\n-1.0\n" % (width, height) + np.tile(np.float32(LINEAR), width * height).astype("<f4").tobytes()


def exr(width=SIDE, height=SIDE, pixel_type=1):
    """A scanline EXR without compression, channels B, G, R of pixel_type
    (0 UINT, 1 HALF, 2 FLOAT) holding LINEAR (UINT: 1, 2, 3)."""

    def attribute(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value

    channels = b"".join(c.encode() + b"\0" + struct.pack("<iBxxxii", pixel_type, 0, 1, 1) for c in "BGR") + b"\0"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (b"\x76\x2f\x31\x01" + struct.pack("<I", 2) + attribute("channels", "chlist", channels) +
              attribute("compression", "compression", b"\0") + attribute("dataWindow", "box2i", box) +
              attribute("displayWindow", "box2i", box) + attribute("lineOrder", "lineOrder", b"\0") +
              attribute("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0)) +
              attribute("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    values = {"B": LINEAR[2], "G": LINEAR[1], "R": LINEAR[0]}
    integers = {"B": 3, "G": 2, "R": 1}
    line = b""
    for c in "BGR":
        if pixel_type == 0:
            line += struct.pack("<I", integers[c]) * width
        elif pixel_type == 1:
            line += np.float16(values[c]).tobytes() * width
        else:
            line += struct.pack("<f", values[c]) * width
    chunk_size = 8 + len(line)
    table_end = len(header) + 8 * height
    table = b"".join(struct.pack("<Q", table_end + y * chunk_size) for y in range(height))
    chunks = b"".join(struct.pack("<ii", y, len(line)) + line for y in range(height))
    return header + table + chunks


# Valid images: name -> (bytes, expected linear RGB of every texel).
def valid_images():
    srgb = tuple(srgb_to_linear(c) for c in COLOUR)
    grey = srgb_to_linear(JPEG_GREY)
    return {
        "valid.png": (png(), srgb),
        "valid-palette.png": (png_palette(), srgb),
        "valid-interlaced.png": (png_interlaced_palette(), srgb),
        "valid.tga": (tga(), srgb),
        "valid-rle.tga": (tga(rle=True), srgb),
        "valid.bmp": (bmp(), srgb),
        "valid-palette.bmp": (bmp_palette(index=1), srgb),
        "valid.hdr": (hdr(), LINEAR),
        "valid-flat.hdr": (hdr(width=4, height=4, rle=False), LINEAR),
        "valid.jpg": (jpeg(width=16, height=16), (grey, grey, grey)),
        "valid.gif": (gif(), srgb),
        "valid.psd": (psd(), srgb),
        "valid.ppm": (ppm(), srgb),
        "valid-16.pgm": (pgm16(), (srgb[1],) * 3),
        "valid.pic": (pic(), srgb),
        "valid.pfm": (pfm(), LINEAR),
        "valid.exr": (exr(), LINEAR),
        "valid-float.exr": (exr(pixel_type=2), LINEAR),
    }


def cut(data, keep):
    return data[:keep]


# Malformed images: name -> (bytes, text the error must hold).
def malformed_images():
    return {
        "no-pixels.tga": (tga(64, 64, header_only=True), "truncated"),
        "last-byte.tga": (tga()[:-1], "truncated"),
        "cut-rle.tga": (tga(64, 64, rle=True)[:-3], "truncated"),
        "cut.bmp": (bmp()[:-40], "truncated"),
        "palette-index.bmp": (bmp_palette(index=3, entries=2), "palette"),
        "cut.hdr": (hdr()[:-5], "truncated"),
        "cut-flat.hdr": (hdr(width=4, height=4, rle=False)[:-1], "truncated"),
        "zero-count.hdr": (hdr().replace(bytes([128 + 8, 192]), bytes([0, 192]), 1), "bad run-length"),
        "cut.png": (png(64, 64)[:-30], "truncated"),
        "cut-idat.png": (png(64, 64)[:60], "truncated"),
        "palette-index.png": (png_palette(index=5, entries=2), "palette"),
        "interlaced-index.png": (png_interlaced_palette(index=2), "palette"),
        "cut.jpg": (jpeg(width=64, height=64)[:-6], "truncated"),
        "no-eoi.jpg": (jpeg(width=16, height=16)[:-2], "truncated"),
        "bomb.tga": (tga(26000, 26000, header_only=True), "over the limit"),
        "bomb.bmp": (bmp(26000, 26000, header_only=True), "over the limit"),
        "bomb.hdr": (hdr(header_size=(26000, 26000)), "over the limit"),
        "bomb.png": (png(1, 1, ihdr_size=(26000, 26000)), "over the limit"),
        "small-bomb.png": (png(1, 1, ihdr_size=(16000, 16000)), "truncated"),
        "bomb.jpg": (jpeg(width=8, height=8, header_size=(20000, 20000), scan_bytes=b"\x3f" * 1400), "over the limit"),
        "small-bomb.jpg": (jpeg(width=8, height=8, header_size=(16000, 16000), scan_bytes=b"\x3f" * 1400),
                           "truncated"),
        "bomb.gif": (gif(1, 1, screen=(26000, 26000)), "over the limit"),
        "bomb.psd": (psd(header_size=(26000, 26000)), "over the limit"),
        "bomb.ppm": (ppm(header_size=(26000, 26000)), "over the limit"),
        "bomb.pic": (pic(header_size=(16000, 16000)), "truncated"),
        "small-bomb.hdr": (hdr(header_size=(16000, 16000)), "truncated"),
        "uint.exr": (exr(pixel_type=0), "UINT"),
        "escape-chunk.png": (png_odd_chunk(b"\x1b[2J"), "PNG chunk"),
        "nul-chunk.png": (png_odd_chunk(b"\0\0\0\0"), "PNG chunk"),
        "empty.png": (b"", "empty file"),
        "text.png": (b"\x1b[31mnot an image\n", "not an image"),
    }
