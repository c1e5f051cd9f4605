#!/usr/bin/env python3
"""Writes the committed seed corpora, fuzz/corpus/<target>/ (a few KB each).

    python3 fuzz/make_seeds.py --illum build/release/bin/illum --shared ../shared/scenes

Everything is generated here (PNG, Radiance HDR and uncompressed OpenEXR are encoded by hand
below; glTF/GLB, OBJ/MTL and scene files are written out) except three kinds of seed:
the JPEG and the light-map folders come from the `illum` program (`illum render` to .jpg,
`illum bake --resolution 16` in the three bases), and two trimmed files come from the shared
scenes (the top scanline of a 1k Radiance HDR environment map, header adjusted, and the
first 2 KiB of a Sibenik JPEG: a header with truncated pixel data). Files the harnesses name (scene.mtl, mesh.obj, tex.png, ...) are
the fixed companions of fuzz/fuzz_support.h. Run it again after changing a format; the
output is deterministic.
"""
import argparse
import base64
import json
import os
import shutil
import struct
import subprocess
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
NEXT_FILE = b"\n--illum-fuzz-next-file--\n"  # fuzz_support.h: kNextFile


def write(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# --- images -----------------------------------------------------------------------------

def png(width, height, colour_type, bit_depth, rows, palette=None, trns=None):
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))
    raw = b"".join(b"\x00" + row for row in rows)
    out = b"\x89PNG\r\n\x1a\n"
    out += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0))
    if palette:
        out += chunk(b"PLTE", palette)
    if trns:
        out += chunk(b"tRNS", trns)
    out += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    return out


def rgbe(r, g, b):
    import math
    m = max(r, g, b)
    if m < 1e-32:
        return b"\x00\x00\x00\x00"
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes([int(r * scale), int(g * scale), int(b * scale), exponent + 128])


def hdr_flat(width, height):
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (height, width)
    body = b"".join(rgbe(0.1 * x, 0.2 * y, 1.5) for y in range(height) for x in range(width))
    return head + body


def hdr_rle(width, height):
    # New-style RLE scanlines (width 8..32767): 2 2 hi lo, then each channel as runs
    # (count > 128: one value repeated count-128 times) and literal dumps (count ≤ 128).
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (height, width)
    body = b""
    for y in range(height):
        pixels = [rgbe(0.05 * x + 0.01, 0.3, 0.1 * y + 0.2) for x in range(width)]
        body += bytes([2, 2, width >> 8, width & 0xFF])
        for c in range(4):
            values = bytes(p[c] for p in pixels)
            half = width // 2
            body += bytes([half]) + values[:half]                  # literal dump
            body += bytes([128 + width - half, values[half]])      # run
    return head + body


def hdr_first_rows(data, rows):
    """A new-style RLE Radiance file cut to its first `rows` scanlines, header adjusted."""
    end = data.index(b"\n\n") + 2
    size_line_end = data.index(b"\n", end)
    size = data[end:size_line_end].split()  # -Y height +X width
    width = int(size[3])
    head = data[:end] + b"-Y %d +X %d\n" % (rows, width)
    at = size_line_end + 1
    start = at
    for _ in range(rows):
        assert data[at] == 2 and data[at + 1] == 2, "not a new-style RLE scanline"
        at += 4
        for _channel in range(4):
            filled = 0
            while filled < width:
                count = data[at]
                if count > 128:
                    filled += count - 128
                    at += 2
                else:
                    filled += count
                    at += 1 + count
    return head + data[start:at]


def exr(width, height, channels, pixel_type):
    """Single-part scanline OpenEXR, no compression. pixel_type 1 = half, 2 = float."""
    def attr(name, kind, value):
        return name + b"\0" + kind + b"\0" + struct.pack("<i", len(value)) + value
    chlist = b"".join(name + b"\0" + struct.pack("<iB3xii", pixel_type, 0, 1, 1)
                      for name in sorted(channels)) + b"\0"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = b"\x76\x2f\x31\x01" + struct.pack("<i", 2)
    header += attr(b"channels", b"chlist", chlist)
    header += attr(b"compression", b"compression", b"\0")
    header += attr(b"dataWindow", b"box2i", box)
    header += attr(b"displayWindow", b"box2i", box)
    header += attr(b"lineOrder", b"lineOrder", b"\0")
    header += attr(b"pixelAspectRatio", b"float", struct.pack("<f", 1.0))
    header += attr(b"screenWindowCenter", b"v2f", struct.pack("<ff", 0.0, 0.0))
    header += attr(b"screenWindowWidth", b"float", struct.pack("<f", 1.0))
    header += b"\0"
    fmt = "<e" if pixel_type == 1 else "<f"
    blocks = []
    for y in range(height):
        data = b"".join(struct.pack(fmt, 0.25 * (x + 1) + 0.5 * c + 0.125 * y)
                        for c in range(len(channels)) for x in range(width))
        blocks.append(struct.pack("<ii", y, len(data)) + data)
    offset = len(header) + 8 * height
    table = b""
    for block in blocks:
        table += struct.pack("<Q", offset)
        offset += len(block)
    return header + table + b"".join(blocks)


def image_seeds(illum, shared):
    write("image", "rgba8.png", png(4, 4, 6, 8, [bytes(sum(((x * 60, y * 60, 128, 255 - 20 * x)
                                                            for x in range(4)), ()))
                                                 for y in range(4)]))
    write("image", "grey8.png", png(3, 3, 0, 8, [bytes(10 * x + 80 * y for x in range(3))
                                                 for y in range(3)]))
    write("image", "grey_alpha8.png", png(2, 2, 4, 8, [bytes((50, 255, 200, 128)),
                                                       bytes((0, 0, 255, 255))]))
    write("image", "rgb16.png", png(2, 2, 2, 16, [struct.pack(">6H", 0, 1000, 65535, 30000, 2, 3),
                                                  struct.pack(">6H", 9, 8, 7, 6, 5, 4)]))
    write("image", "palette4.png", png(4, 2, 3, 4, [bytes((0x01, 0x23)), bytes((0x32, 0x10))],
                                       palette=bytes(range(12)), trns=b"\x80\xff"))
    write("image", "flat.hdr", hdr_flat(4, 3))
    write("image", "rle.hdr", hdr_rle(8, 2))
    write("image", "rgb_half.exr", exr(4, 4, [b"R", b"G", b"B"], 1))
    write("image", "rgba_float.exr", exr(2, 2, [b"R", b"G", b"B", b"A"], 2))
    write("image", "y_half.exr", exr(3, 2, [b"Y"], 1))
    write("image", "depth_float.exr", exr(2, 2, [b"Z"], 2))
    with tempfile.TemporaryDirectory() as tmp:
        jpg = os.path.join(tmp, "cornell.jpg")
        subprocess.run([illum, "render", "cornell", "--integrator", "albedo", "--width", "8",
                        "--height", "8", "--spp", "1", "--seed", "1", "-o", jpg], check=True)
        write("image", "cornell8.jpg", open(jpg, "rb").read())
    with open(os.path.join(shared, "envmaps", "venice_sunset_1k.hdr"), "rb") as f:
        write("image", "venice_sunset_1k_top_row.hdr", hdr_first_rows(f.read(), 1))
    with open(os.path.join(shared, "sibenik", "KAMEN320x240.jpg"), "rb") as f:
        write("image", "sibenik_kamen_first2k.jpg", f.read(2048))


# --- OBJ/MTL ----------------------------------------------------------------------------

def obj_seeds():
    folder = os.path.join(ROOT, "data", "scenes", "cornell")
    obj = open(os.path.join(folder, "cornell_box.obj"), "rb").read()
    mtl = open(os.path.join(folder, "cornell_box.mtl"), "rb").read()
    obj = b"\n".join(b"mtllib scene.mtl" if line.startswith(b"mtllib") else line
                     for line in obj.split(b"\n"))
    write("obj", "cornell_obj_mtl", obj + NEXT_FILE + mtl)
    write("obj", "textured_obj_mtl", """mtllib scene.mtl
o quad
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl painted
f 1/1/1 2/2/1 3/3/1
usemtl glass
f 1/1/1 3/3/1 4/4/1
o lamp
v 0 0 1
v 1 0 1
v 0 1 1
usemtl glow
f 5 6 7
o chrome
usemtl chrome
f 2 3 6
o shiny
usemtl shiny
f -1 -2 -3
""" + NEXT_FILE.decode() + """newmtl painted
Kd 0.8 0.5 0.2
map_Kd -clamp on tex.png
norm -bm 0.5 normal.png
d 0.9
newmtl glass
illum 7
Ni 1.33
Tf 0.9 0.95 1
newmtl glow
Kd 0 0 0
map_Ke tex.hdr
newmtl chrome
illum 3
Ks 0.9 0.9 0.9
newmtl shiny
illum 2
Kd 0.3 0.3 0.3
Ks 0.2 0.2 0.2
Ns 64
map_bump tex.jpg
""")
    write("obj", "polygons_companion_mtl", """# no second part: scene.mtl is absent; mesh.mtl is a companion
mtllib mesh.mtl
g first second
s 1
v 0 0 0
v 1 0 0
v 1.5 0.8 0
v 0.5 1.4 0
v -0.5 0.8 0
v 0 0 1
usemtl white
f 1 2 3 4 5
s off
f -1 -5 -4
l 1 2 3
p 4
o light
usemtl light
f 1//1 6//1 2//1
vn 0 0 -1
""")


# --- glTF -------------------------------------------------------------------------------

def quad_buffer():
    positions = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    normals = struct.pack("<12f", *([0, 0, 1] * 4))
    uvs = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    return positions + normals + uvs + indices  # 48 + 48 + 32 + 12 = 140 bytes


def quad_gltf(buffer_entry, image_entry, extra_buffer_views=()):
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
             {"buffer": 0, "byteOffset": 48, "byteLength": 48},
             {"buffer": 0, "byteOffset": 96, "byteLength": 32},
             {"buffer": 0, "byteOffset": 128, "byteLength": 12}] + list(extra_buffer_views)
    return {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0, 3, 4]}],
        "nodes": [
            {"name": "root", "translation": [0, 1, 0], "rotation": [0, 0.7071068, 0, 0.7071068],
             "scale": [2, 2, 2], "children": [1, 2]},
            {"name": "a", "mesh": 0},
            {"name": "b", "mesh": 0,
             "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 3, 0, 0, 1]},
            {"name": "cam", "camera": 0, "translation": [0, 0, 5]},
            {"name": "lights", "children": [5, 6, 7]},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 3, 0]},
            {"extensions": {"KHR_lights_punctual": {"light": 1}}, "translation": [1, 3, 0]},
            {"extensions": {"KHR_lights_punctual": {"light": 2}}},
        ],
        "meshes": [{"name": "quad", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0, "mode": 4}]}],
        "materials": [{"name": "painted",
                       "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1],
                                                "baseColorTexture": {"index": 0},
                                                "metallicFactor": 0.1, "roughnessFactor": 0.7},
                       "emissiveFactor": [0.1, 0.1, 0.1],
                       "extensions": {"KHR_materials_emissive_strength":
                                      {"emissiveStrength": 2}},
                       "normalTexture": {"index": 0, "scale": 1}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [image_entry],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "znear": 0.01, "zfar": 100,
                                     "aspectRatio": 1.5}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 0.9, 0.8], "intensity": 20},
            {"type": "spot", "intensity": 50, "range": 10,
             "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
            {"type": "directional", "intensity": 3}]}},
        "buffers": [buffer_entry],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }


def glb(document, binary):
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    body = (struct.pack("<I", len(text)) + b"JSON" + text +
            struct.pack("<I", len(binary)) + b"BIN\0" + binary)
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def gltf_seeds():
    buffer = quad_buffer()
    uri = "data:application/octet-stream;base64," + base64.b64encode(buffer).decode()
    write("gltf", "quad_datauri.gltf",
          json.dumps(quad_gltf({"uri": uri, "byteLength": len(buffer)}, {"uri": "tex.png"}),
                     indent=1))
    # The same quad in a GLB whose BIN chunk also holds a 2×2 PNG, read through a bufferView.
    image = png(2, 2, 2, 8, [bytes((255, 0, 0, 0, 255, 0)), bytes((0, 0, 255, 255, 255, 255))])
    padded = buffer + b"\0" * (-len(buffer) % 4)
    document = quad_gltf({"byteLength": len(padded) + len(image)},
                         {"bufferView": 4, "mimeType": "image/png"},
                         [{"buffer": 0, "byteOffset": len(padded), "byteLength": len(image)}])
    write("gltf", "quad_embedded_png.glb", glb(document, padded + image))
    # Interleaved positions/uvs (byteStride 20), uint8 indices, a sparse accessor that moves
    # one vertex, and the companion buffer.bin for a second mesh.
    inter = b"".join(struct.pack("<5f", x, y, 0, x, y) for x, y in ((0, 0), (1, 0), (0, 1)))
    idx = bytes((0, 1, 2, 0))
    sparse_idx = struct.pack("<H", 2) + b"\0\0"
    sparse_val = struct.pack("<3f", 0.5, 1.5, 0.25)
    data = inter + idx + sparse_idx + sparse_val
    uri = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    write("gltf", "interleaved_sparse.gltf", json.dumps({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 1, "scale": [1, 1, -1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                    "indices": 2}]},
                   {"primitives": [{"attributes": {"POSITION": 3}, "indices": 4}]}],
        "buffers": [{"uri": uri, "byteLength": len(data)},
                    {"uri": "buffer.bin", "byteLength": 44}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 60, "byteStride": 20},
                        {"buffer": 0, "byteOffset": 60, "byteLength": 3},
                        {"buffer": 0, "byteOffset": 64, "byteLength": 2},
                        {"buffer": 0, "byteOffset": 68, "byteLength": 12},
                        {"buffer": 1, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 1, "byteOffset": 36, "byteLength": 6}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0],
             "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5123},
                        "values": {"bufferView": 3}}},
            {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 3,
             "type": "VEC2"},
            {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"},
            {"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 5, "componentType": 5123, "count": 3, "type": "SCALAR"}]},
        indent=1))


# --- illum scene files ------------------------------------------------------------------

def illum_json_seeds():
    write("illum_json", "every_key.illum.json", """{
  // every key of docs/scene-format.md, over the companion files
  "name": "demo",
  "description": "free text",
  "meshes": [
    {"file": "mesh.obj", "scale": 0.5,
     "transform": {"translate": [0, 0, 1], "rotate_deg": [0, 90, 0], "scale": [1, 2, 1]},
     "hide": ["lamp"]},
    {"file": "mesh.gltf", "transform": {"scale": 2}}
  ],
  "materials": {
    "white": {"type": "phong", "albedo": [0.6, 0.5, 0.4], "specular": [0.1, 0.1, 0.1],
              "exponent": 32, "roughness": 0.5, "ior": 1.5, "transmittance": [1, 1, 1],
              "eta": [0.2, 0.92, 1.1], "k": [3.9, 2.45, 2.14], "emission": [0, 0, 0],
              "opacity": 1, "albedo_texture": "tex.png", "normal_texture": "normal.png"}
  },
  "lights": [
    {"type": "point", "position": [0, 2, 0], "flux": 100, "color": [1, 1, 1]},
    {"type": "point", "position": [0, 2, 0], "intensity": 7.96},
    {"type": "spot", "position": [0, 1.5, 0], "direction": [0, -1, 0],
     "half_angle_deg": 25, "flux": 100, "color": [1, 1, 1], "range": 0},
    {"type": "sun", "direction": [0.354, -0.866, -0.354], "irradiance": 10,
     "color": [1, 0.92, 0.8]},
    {"type": "directional", "direction": [0, -1, 0], "irradiance": 1}
  ],
  "environment": {"file": "env.hdr", "scale": 1, "rotation_deg": 30},
  "camera": {"position": [0.278, 0.273, -0.8], "look_at": [0.278, 0.273, 0],
             "up": [0, 1, 0], "fov_y_deg": 39.3077},
  "settings": {"width": 64, "height": 48, "spp": 4, "max_bounces": 8,
               "ambient": [0.03, 0.03, 0.03]}
}
""")
    cornell = open(os.path.join(ROOT, "data", "scenes", "cornell", "cornell.illum.json")).read()
    write("illum_json", "cornell.illum.json", cornell.replace("cornell_box.obj", "mesh.obj"))
    write("illum_json", "gltf_constant_sky.illum.json", """{
  "meshes": [{"file": "mesh.gltf", "hide": []}],
  "materials": {"white": {"type": "dielectric", "ior": 1.33, "emission": [0.5, 0.5, 0.5]}},
  "environment": {"constant": [0.2, 0.3, 0.5], "scale": 2},
  "settings": {"ambient": [0, 0, 0]}
}
""")
    write("illum_json", "exr_sky_mirror.illum.json", """{
  "meshes": [{"file": "mesh.obj"}],
  "materials": {"light": {"type": "mirror", "specular": [0.9, 0.9, 0.9]},
                "white": {"type": "conductor", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1],
                          "roughness": 0.2}},
  "environment": {"file": "env.exr", "rotation_deg": -90}
}
""")


# --- light-map folders ------------------------------------------------------------------

def lightmap_seeds(illum):
    for basis in ("plain", "rnm", "sh"):
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "lm")
            subprocess.run([illum, "bake", "cornell", "-o", out, "--basis", basis,
                            "--resolution", "16", "--spp", "1", "--seed", "1", "--threads", "1"],
                           check=True, stdout=subprocess.DEVNULL)
            manifest = json.load(open(os.path.join(out, "lightmap.json")))
            assert manifest["width"] == 16 and manifest["height"] == 16, manifest
            # The bake's own figures (seconds, rays) change from run to run; the loader keeps
            # them as free-form JSON, so fixed numbers do as well.
            manifest["bake"] = {"spp": 1, "seconds": 0.5}
            text = json.dumps(manifest, indent=2).encode()
            atlas = open(os.path.join(out, "atlas.bin"), "rb").read()
            write("lightmap", "cornell_" + basis, text + NEXT_FILE + atlas)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--illum", required=True, help="the illum program")
    parser.add_argument("--shared", default=os.path.join(ROOT, "..", "shared", "scenes"),
                        help="the shared scenes folder")
    args = parser.parse_args()
    for target in ("image", "obj", "gltf", "illum_json", "lightmap"):
        shutil.rmtree(os.path.join(HERE, "corpus", target), ignore_errors=True)
    image_seeds(args.illum, args.shared)
    obj_seeds()
    gltf_seeds()
    illum_json_seeds()
    lightmap_seeds(args.illum)


if __name__ == "__main__":
    main()
