#!/usr/bin/env bash
# Seeds the fuzz corpora (fuzz/corpus/TARGET, not committed):
#   parse, scene  the small scene files of ../pbrt-scenes and ../../shared/scenes
#                 (public repositories under their own licences)
#   ply           small PLY files written here (ASCII, both binary byte
#                 orders, normals, uvs, quads, face_indices, gzip) and the
#                 small PLY files of ../../shared/scenes
#   image         tiny PFM, TGA and PNG images written here, EXR and PNG
#                 copies written by `rpbrt imgtool convert` (if built), and
#                 any tiny JPEG/EXR/PNG test images Python ships; the image
#                 target's first byte picks the format (0 exr, 1 pfm, 2 png,
#                 3 tga, 4 jpg)
#   cyhair        small CyHair files written here (every optional array,
#                 with and without a segments array)
set -eu
cd "$(dirname "$0")"
mkdir -p corpus/parse corpus/scene corpus/ply corpus/image corpus/cyhair
find ../../shared/scenes ../pbrt-scenes -name '*.pbrt' -size -64k -exec cp {} corpus/parse/ \;
find ../../shared/scenes ../pbrt-scenes -name '*.pbrt' -size -64k -exec cp {} corpus/scene/ \;
find ../../shared/scenes -name '*.ply' -size -16k -exec cp {} corpus/ply/ \; 2>/dev/null || true

RPBRT=${RPBRT:-../target/release/rpbrt}
python3 - "$RPBRT" <<'PY'
import gzip, os, struct, subprocess, sys, tempfile, zlib

rpbrt = sys.argv[1]

def put(target, name, data):
    with open(os.path.join("corpus", target, name), "wb") as f:
        f.write(data)

# PLY
verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
def ply(fmt, normals=False, uvs=None, quads=False, face_indices=False):
    props = ["float x", "float y", "float z"]
    if normals:
        props += ["float nx", "float ny", "float nz"]
    if uvs:
        props += [f"float {uvs[0]}", f"float {uvs[1]}"]
    faces = [[0, 1, 2, 3], [0, 1, 4]] if quads else [[0, 1, 2], [0, 2, 3], [2, 3, 4]]
    head = f"ply\nformat {fmt} 1.0\nelement vertex {len(verts)}\n"
    head += "".join(f"property {p}\n" for p in props)
    head += f"element face {len(faces)}\nproperty list uchar int vertex_indices\n"
    if face_indices:
        head += "property int face_indices\n"
    head += "end_header\n"
    rows = []
    for i, v in enumerate(verts):
        row = list(v)
        if normals:
            row += [0, 0, 1]
        if uvs:
            row += [v[0], v[1]]
        rows.append(row)
    if fmt == "ascii":
        body = "".join(" ".join(str(x) for x in r) + "\n" for r in rows)
        for i, f in enumerate(faces):
            body += " ".join(str(x) for x in [len(f)] + f + ([i] if face_indices else [])) + "\n"
        return head.encode() + body.encode()
    e = "<" if fmt == "binary_little_endian" else ">"
    body = b"".join(struct.pack(e + "f" * len(r), *r) for r in rows)
    for i, f in enumerate(faces):
        body += struct.pack(e + "B" + "i" * len(f), len(f), *f)
        if face_indices:
            body += struct.pack(e + "i", i)
    return head.encode() + body
for fmt in ["ascii", "binary_little_endian", "binary_big_endian"]:
    put("ply", f"{fmt}.ply", ply(fmt))
    put("ply", f"{fmt}-all.ply", ply(fmt, True, ("u", "v"), True, True))
put("ply", "st.ply", ply("ascii", uvs=("s", "t"), quads=True))
put("ply", "texture_uv.ply", ply("binary_little_endian", uvs=("texture_u", "texture_v")))
put("ply", "gzip.ply.gz", gzip.compress(ply("binary_little_endian", True, ("u", "v"))))

# Images: 4 × 3, first byte = format (0 exr, 1 pfm, 2 png, 3 tga, 4 jpg).
W, H = 4, 3
rgb = [((x * 60) % 256, (y * 90) % 256, ((x + y) * 40) % 256) for y in range(H) for x in range(W)]
def pfm(grey, little):
    e = "<" if little else ">"
    head = b"Pf" if grey else b"PF"
    head += f"\n{W} {H}\n{-1.0 if little else 2.0}\n".encode()
    vals = []
    for y in reversed(range(H)):
        for x in range(W):
            r, g, b = rgb[y * W + x]
            vals += [r / 255] if grey else [r / 255, g / 255, b / 255]
    return head + struct.pack(e + "f" * len(vals), *vals)
def png(colour_type, depth=8):
    chans = {0: 1, 2: 3, 4: 2, 6: 4}[colour_type]
    raw = b""
    for y in range(H):
        raw += b"\0"
        for x in range(W):
            px = (list(rgb[y * W + x]) + [200])[:chans] if chans != 2 else [rgb[y * W + x][0], 200]
            raw += b"".join(struct.pack(">H", v * 257) if depth == 16 else bytes([v]) for v in px)
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, depth, colour_type, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
def tga(alpha, rle):
    bpp = 32 if alpha else 24
    head = struct.pack("<BBBHHBHHHHBB", 0, 0, 10 if rle else 2, 0, 0, 0, 0, 0, W, H, bpp, 8 if alpha else 0)
    body = b""
    for (r, g, b) in rgb:
        px = bytes([b, g, r] + ([200] if alpha else []))
        body += (b"\x00" + px) if rle else px
    return head + body
put("image", "grey-le.pfm", b"\1" + pfm(True, True))
put("image", "rgb-be.pfm", b"\1" + pfm(False, False))
for ct in [0, 2, 4, 6]:
    put("image", f"ct{ct}.png", b"\2" + png(ct))
put("image", "rgb16.png", b"\2" + png(2, 16))
put("image", "rgb.tga", b"\3" + tga(False, False))
put("image", "rgba-rle.tga", b"\3" + tga(True, True))
if os.path.exists(rpbrt):
    with tempfile.TemporaryDirectory() as d:
        src = os.path.join(d, "in.pfm")
        with open(src, "wb") as f:
            f.write(pfm(False, True))
        for ext, tag in [("exr", b"\0"), ("png", b"\2")]:
            out = os.path.join(d, "out." + ext)
            if subprocess.run([rpbrt, "imgtool", "convert", "--outfile", out, src],
                              capture_output=True).returncode == 0:
                with open(out, "rb") as f:
                    put("image", "rpbrt." + ext, tag + f.read())
import glob
for path in sorted(glob.glob(os.path.expanduser("~/.pyenv/versions/*/lib/python3*/test/*/python.*")))[:40]:
    ext = path.rsplit(".", 1)[1]
    tag = {"exr": b"\0", "png": b"\2", "jpg": b"\4"}.get(ext)
    if tag and os.path.getsize(path) < 16384:
        with open(path, "rb") as f:
            put("image", "python-" + ext + "-" + str(abs(hash(path)) % 1000), tag + f.read())

# CyHair: flags bit 0 segments, 1 points, 2 thickness, 3 transparency, 4 colour.
def hair(segments, flags, default_segments=2):
    points = sum(s + 1 for s in segments)
    head = b"HAIR" + struct.pack("<IIII", len(segments), points, flags, default_segments)
    head += struct.pack("<fffff", 0.1, 0.0, 0.5, 0.4, 0.3)
    head += b"fuzz seed".ljust(88, b"\0")
    body = b""
    if flags & 1:
        body += struct.pack("<" + "H" * len(segments), *segments)
    body += struct.pack("<" + "f" * 3 * points, *[i * 0.25 for i in range(3 * points)])
    if flags & 4:
        body += struct.pack("<" + "f" * points, *[0.05] * points)
    if flags & 8:
        body += struct.pack("<" + "f" * points, *[0.1] * points)
    if flags & 16:
        body += struct.pack("<" + "f" * 3 * points, *[0.5] * 3 * points)
    return head + body
put("cyhair", "points.hair", hair([2, 2], 2))
put("cyhair", "segments.hair", hair([1, 3, 2], 3))
put("cyhair", "all.hair", hair([3, 1], 31))
put("cyhair", "thickness.hair", hair([2, 2, 2], 6))
PY
for t in parse scene ply image cyhair; do echo "$t: $(ls corpus/$t | wc -l)"; done
