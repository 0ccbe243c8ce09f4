#!/usr/bin/env python3
"""Generate the HRPP project's own test scenes as glTF 2.0 binaries (.glb).

Usage:
    python3 scenes/gen_scenes.py [--out DIR]   write every scene to DIR
                                               (default: this script's folder)
    python3 scenes/gen_scenes.py --check       regenerate in memory and compare
                                               byte for byte with the files next
                                               to this script (exit 1 on any
                                               difference or missing file)

Each scene NAME is written as NAME.glb plus a camera sidecar NAME.camera.json.
The conventions are those of the shared scene set (see scenes/README.md):
one buffer; one mesh with one TRIANGLES primitive per mesh node (POSITION
float32 VEC3 with min/max, uint32 indices, a material); identity transforms
on mesh nodes (vertices are in world space); punctual lights through
KHR_lights_punctual on mesh-less nodes (point: translation only,
directional: rotation only, shining along the node's -Z); area lights as
one-sided emissive triangle meshes wound so that (v1-v0)x(v2-v0) points
where the light goes.

Output is deterministic: no timestamps, fixed JSON key order and
separators, floats packed with struct '<f'. Geometry is computed with
+ - * / and sqrt only (all correctly rounded in IEEE 754, plus the exact
math.frexp and math.ldexp), so the binary chunks do not depend on the
platform's libm.

Standard library only (Python 3.11).
"""

import argparse
import hashlib
import json
import math
import struct
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the pyhrpp package
from pyhrpp.files import write_atomic  # noqa: E402

GENERATOR = "hrpp scenes/gen_scenes.py"

GLB_MAGIC = 0x46546C67  # "glTF"
CHUNK_JSON = 0x4E4F534A  # "JSON"
CHUNK_BIN = 0x004E4942  # "BIN\0"
TARGET_ARRAY_BUFFER = 34962
TARGET_ELEMENT_ARRAY_BUFFER = 34963
FLOAT = 5126
UNSIGNED_INT = 5125


# --------------------------------------------------------------------------
# small vector helpers (double precision)
# --------------------------------------------------------------------------

def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = length(a)
    return (a[0] / n, a[1] / n, a[2] / n)


def rotate(v, axis, cos_t, sin_t):
    """Rodrigues rotation of v about the unit vector axis (right-handed),
    given the cosine and sine of the angle (so no trigonometric call)."""
    kxv = cross(axis, v)
    kdv = dot(axis, v)
    return (v[0] * cos_t + kxv[0] * sin_t + axis[0] * kdv * (1.0 - cos_t),
            v[1] * cos_t + kxv[1] * sin_t + axis[1] * kdv * (1.0 - cos_t),
            v[2] * cos_t + kxv[2] * sin_t + axis[2] * kdv * (1.0 - cos_t))


def rotation_between(a, b):
    """(axis, cos, sin) of the rotation taking unit vector a to unit vector b
    (None for identity). Not used for antiparallel vectors."""
    c = cross(a, b)
    s = length(c)
    cos_t = dot(a, b)
    if s == 0.0:
        if cos_t > 0.0:
            return None
        raise ValueError("antiparallel vectors")
    return (scale(c, 1.0 / s), cos_t, s)


def quat_from_to(a, b):
    """Unit quaternion (x, y, z, w) rotating unit vector a onto unit vector b."""
    c = cross(a, b)
    w = 1.0 + dot(a, b)
    n = math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + w * w)
    return (c[0] / n, c[1] / n, c[2] / n, w / n)


def quat_rotate(q, v):
    x, y, z, w = q
    u = (x, y, z)
    t = scale(cross(u, v), 2.0)
    return add(add(v, scale(t, w)), cross(u, t))


def f32(x):
    """Round a double to the nearest float32 (and turn -0.0 into 0.0)."""
    return struct.unpack("<f", struct.pack("<f", x + 0.0))[0] + 0.0


def r6(x):
    """Round a JSON number for readability (6 decimals, no negative zero)."""
    return round(x, 6) + 0.0


def r6v(v):
    return [r6(x) for x in v]


# --------------------------------------------------------------------------
# glTF builder
# --------------------------------------------------------------------------

class Gltf:
    def __init__(self, scene_name, source):
        self.scene_name = scene_name
        self.source = source
        self.bin = bytearray()
        self.buffer_views = []
        self.accessors = []
        self.meshes = []
        self.materials = []
        self.nodes = []
        self.lights = []
        self.extensions_used = set()
        self.triangles = 0
        self.vertices = 0
        self.bbox_min = [math.inf] * 3
        self.bbox_max = [-math.inf] * 3
        self.node_summary = []

    # -- buffer -----------------------------------------------------------
    def _buffer_view(self, data, target):
        assert len(self.bin) % 4 == 0 and len(data) % 4 == 0
        offset = len(self.bin)
        self.bin += data
        self.buffer_views.append({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": len(data),
            "target": target,
        })
        return len(self.buffer_views) - 1

    # -- materials ----------------------------------------------------------
    def material(self, name, base_color, metallic, roughness, source,
                 emissive=None, emissive_strength=None, double_sided=True,
                 transmission=None, ior=None):
        m = {
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": r6v(base_color) + [1.0],
                "metallicFactor": r6(metallic),
                "roughnessFactor": r6(roughness),
            },
        }
        if emissive is not None:
            m["emissiveFactor"] = r6v(emissive)
        m["doubleSided"] = bool(double_sided)
        ext = {}
        if emissive_strength is not None:
            assert emissive is not None and emissive_strength > 1.0
            ext["KHR_materials_emissive_strength"] = {
                "emissiveStrength": r6(emissive_strength)}
        if transmission is not None:
            ext["KHR_materials_transmission"] = {
                "transmissionFactor": r6(transmission)}
        if ior is not None:
            ext["KHR_materials_ior"] = {"ior": r6(ior)}
        if ext:
            m["extensions"] = ext
            self.extensions_used.update(ext.keys())
        m["extras"] = {"source": source}
        self.materials.append(m)
        return len(self.materials) - 1

    # -- meshes -------------------------------------------------------------
    def mesh_node(self, name, positions, triangles, material):
        """positions: list of (x, y, z) doubles in world space;
        triangles: list of (i0, i1, i2)."""
        pos = [(f32(p[0]), f32(p[1]), f32(p[2])) for p in positions]
        used = set()
        for tri in triangles:
            i0, i1, i2 = tri
            if len({i0, i1, i2}) != 3:
                raise ValueError(f"{name}: repeated vertex index in {tri}")
            for i in tri:
                if not 0 <= i < len(pos):
                    raise ValueError(f"{name}: index {i} out of range")
            n = cross(sub(pos[i1], pos[i0]), sub(pos[i2], pos[i0]))
            if dot(n, n) == 0.0:
                raise ValueError(f"{name}: zero-area triangle {tri}")
            used.update(tri)
        if len(used) != len(pos):
            raise ValueError(f"{name}: unreferenced vertices")

        pmin = [min(p[k] for p in pos) for k in range(3)]
        pmax = [max(p[k] for p in pos) for k in range(3)]
        pdata = struct.pack("<%df" % (3 * len(pos)),
                            *[c for p in pos for c in p])
        idata = struct.pack("<%dI" % (3 * len(triangles)),
                            *[i for t in triangles for i in t])
        pview = self._buffer_view(pdata, TARGET_ARRAY_BUFFER)
        iview = self._buffer_view(idata, TARGET_ELEMENT_ARRAY_BUFFER)
        self.accessors.append({
            "bufferView": pview,
            "componentType": FLOAT,
            "count": len(pos),
            "type": "VEC3",
            "min": pmin,
            "max": pmax,
        })
        pacc = len(self.accessors) - 1
        flat = [i for t in triangles for i in t]
        self.accessors.append({
            "bufferView": iview,
            "componentType": UNSIGNED_INT,
            "count": len(flat),
            "type": "SCALAR",
            "min": [min(flat)],
            "max": [max(flat)],
        })
        iacc = len(self.accessors) - 1
        self.meshes.append({
            "name": name,
            "primitives": [{
                "attributes": {"POSITION": pacc},
                "indices": iacc,
                "mode": 4,
                "material": material,
            }],
        })
        self.nodes.append({"name": name, "mesh": len(self.meshes) - 1})
        self.triangles += len(triangles)
        self.vertices += len(pos)
        for k in range(3):
            self.bbox_min[k] = min(self.bbox_min[k], pmin[k])
            self.bbox_max[k] = max(self.bbox_max[k], pmax[k])
        self.node_summary.append((name, len(triangles), len(pos)))
        return pos

    # -- punctual lights -----------------------------------------------------
    def _light(self, light):
        self.extensions_used.add("KHR_lights_punctual")
        self.lights.append(light)
        return len(self.lights) - 1

    def point_light(self, name, position, color, intensity, source):
        li = self._light({
            "type": "point",
            "color": r6v(color),
            "intensity": r6(intensity),
            "name": name,
            "extras": {"source": source},
        })
        self.nodes.append({
            "name": name,
            "translation": r6v(position),
            "extensions": {"KHR_lights_punctual": {"light": li}},
        })
        self.node_summary.append((name, 0, 0))

    def directional_light(self, name, rotation, color, intensity, source):
        li = self._light({
            "type": "directional",
            "color": r6v(color),
            "intensity": r6(intensity),
            "name": name,
            "extras": {"source": source},
        })
        # full precision so that the quaternion stays unit length
        self.nodes.append({
            "name": name,
            "rotation": [x + 0.0 for x in rotation],
            "extensions": {"KHR_lights_punctual": {"light": li}},
        })
        self.node_summary.append((name, 0, 0))

    # -- output --------------------------------------------------------------
    def json_dict(self):
        doc = {
            "asset": {"version": "2.0", "generator": GENERATOR},
            "scene": 0,
            "scenes": [{
                "name": self.scene_name,
                "nodes": list(range(len(self.nodes))),
                "extras": {"source": self.source},
            }],
            "nodes": self.nodes,
            "meshes": self.meshes,
            "materials": self.materials,
            "accessors": self.accessors,
            "bufferViews": self.buffer_views,
            "buffers": [{"byteLength": len(self.bin)}],
        }
        if self.lights:
            doc["extensions"] = {"KHR_lights_punctual": {"lights": self.lights}}
        if self.extensions_used:
            doc["extensionsUsed"] = sorted(self.extensions_used)
        return doc

    def glb(self):
        js = json.dumps(self.json_dict(), separators=(",", ":"),
                        sort_keys=False, ensure_ascii=True,
                        allow_nan=False).encode("ascii")
        js += b" " * ((4 - len(js) % 4) % 4)
        bin_chunk = bytes(self.bin) + b"\0" * ((4 - len(self.bin) % 4) % 4)
        total = 12 + 8 + len(js) + 8 + len(bin_chunk)
        out = bytearray()
        out += struct.pack("<III", GLB_MAGIC, 2, total)
        out += struct.pack("<II", len(js), CHUNK_JSON) + js
        out += struct.pack("<II", len(bin_chunk), CHUNK_BIN) + bin_chunk
        assert len(out) == total
        return bytes(out)


def camera_json(eye, target, up, fov_y_deg, aspect, image_size, kind,
                source, notes):
    cam = {
        "eye": r6v(eye),
        "target": r6v(target),
        "up": r6v(up),
        "fov_y_deg": r6(fov_y_deg),
        "aspect": r6(aspect),
        "image_size": [int(image_size[0]), int(image_size[1])],
        "kind": kind,
        "source": source,
        "notes": notes,
    }
    return (json.dumps(cam, indent=2, sort_keys=False, ensure_ascii=True)
            + "\n").encode("ascii")


def quad(v0, v1, v2, v3):
    """Positions and triangles (v0,v1,v2),(v0,v2,v3) of one quad."""
    return [v0, v1, v2, v3], [(0, 1, 2), (0, 2, 3)]


def quads(qs):
    pos, tris = [], []
    for q in qs:
        base = len(pos)
        pos.extend(q)
        tris.append((base, base + 1, base + 2))
        tris.append((base, base + 2, base + 3))
    return pos, tris


def check_facing(name, pos, tris, direction):
    """Assert that every triangle's geometric normal points along direction."""
    for t in tris:
        n = cross(sub(pos[t[1]], pos[t[0]]), sub(pos[t[2]], pos[t[0]]))
        if dot(normalize(n), direction) < 0.999999:
            raise AssertionError(f"{name}: triangle {t} faces {n}")


def check_outward(name, pos, tris, center):
    """Assert that every triangle of a closed convex shape is wound outwards."""
    for t in tris:
        a, b, c = pos[t[0]], pos[t[1]], pos[t[2]]
        n = cross(sub(b, a), sub(c, a))
        centroid = scale(add(add(a, b), c), 1.0 / 3.0)
        if dot(n, sub(centroid, center)) <= 0.0:
            raise AssertionError(f"{name}: triangle {t} wound inwards")


# --------------------------------------------------------------------------
# icosphere
# --------------------------------------------------------------------------

def unit_icosphere(subdivisions):
    """Icosahedron subdivided `subdivisions` times (each triangle split in
    4 at its edge midpoints), all vertices projected onto the unit sphere,
    triangles wound outwards. 20*4^n triangles, 10*4^n+2 vertices."""
    p = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1.0, p, 0.0), (1.0, p, 0.0), (-1.0, -p, 0.0), (1.0, -p, 0.0),
             (0.0, -1.0, p), (0.0, 1.0, p), (0.0, -1.0, -p), (0.0, 1.0, -p),
             (p, 0.0, -1.0), (p, 0.0, 1.0), (-p, 0.0, -1.0), (-p, 0.0, 1.0)]
    verts = [normalize(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
             (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
             (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
             (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    check_outward("icosahedron", verts, faces, (0.0, 0.0, 0.0))
    for _ in range(subdivisions):
        cache = {}

        def midpoint(i, j):
            key = (i, j) if i < j else (j, i)
            if key not in cache:
                cache[key] = len(verts)
                verts.append(normalize(scale(add(verts[i], verts[j]), 0.5)))
            return cache[key]

        new_faces = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    return verts, faces


# A fixed, generic orientation for the sphereflake's icospheres (axis
# (1,2,3)/sqrt(14), cos 0.8, sin 0.6): with the icosahedron's canonical
# orientation some tessellation vertices sit exactly at the points where
# SPD's true spheres touch each other and the floor, so parent and child
# meshes (and the root sphere and the ground) would touch at a vertex.
FLAKE_ICO_ROT = (normalize((1.0, 2.0, 3.0)), 0.8, 0.6)


def rotated_icosphere(unit, rot):
    verts, faces = unit
    return [rotate(v, *rot) for v in verts], faces


def sphere_mesh(center, radius, unit):
    verts, faces = unit
    return [add(center, scale(v, radius)) for v in verts], list(faces)


def merge(parts):
    pos, tris = [], []
    for p, t in parts:
        base = len(pos)
        pos.extend(p)
        tris.extend((a + base, b + base, c + base) for a, b, c in t)
    return pos, tris


# --------------------------------------------------------------------------
# 1. Cornell box
# --------------------------------------------------------------------------

CORNELL_SOURCE = (
    "Cornell University Program of Computer Graphics, 'Cornell Box Data', "
    "http://www.graphics.cornell.edu/online/box/data.html (geometry in mm, "
    "camera); quads split (v0,v1,v2),(v0,v2,v3); light lowered to y=548.7")

# The published "Cornell Box Data" quads (millimetres), unchanged except for
# the light, which is published at y = 548.8 (coplanar with the ceiling).
CB_FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2),
            (549.6, 0.0, 559.2)]
CB_LIGHT_Y = 548.7
CB_LIGHT = [(343.0, CB_LIGHT_Y, 227.0), (343.0, CB_LIGHT_Y, 332.0),
            (213.0, CB_LIGHT_Y, 332.0), (213.0, CB_LIGHT_Y, 227.0)]
CB_CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2),
              (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
CB_BACK_WALL = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2),
                (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
CB_RIGHT_WALL = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0),
                 (0.0, 548.8, 559.2)]
CB_LEFT_WALL = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2),
                (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]
CB_SHORT_BLOCK = [
    [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0),
     (290.0, 165.0, 114.0)],
    [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0),
     (240.0, 0.0, 272.0)],
    [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0),
     (290.0, 0.0, 114.0)],
    [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0),
     (130.0, 0.0, 65.0)],
    [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0),
     (82.0, 0.0, 225.0)],
]
CB_TALL_BLOCK = [
    [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0),
     (472.0, 330.0, 406.0)],
    [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0),
     (472.0, 0.0, 406.0)],
    [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0),
     (314.0, 0.0, 456.0)],
    [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0),
     (265.0, 0.0, 296.0)],
    [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0),
     (423.0, 0.0, 247.0)],
]


def scene_cornell_box():
    g = Gltf("cornell_box", CORNELL_SOURCE)
    spectra = ("rounded linear-sRGB approximation of the published "
               "Cornell Box Data '%s' reflectance spectrum (400-700 nm, 4 nm)")
    white = g.material("white", (0.74, 0.74, 0.74), 0.0, 1.0,
                       spectra % "white")
    red = g.material("red", (0.49, 0.05, 0.05), 0.0, 1.0, spectra % "red")
    green = g.material("green", (0.07, 0.40, 0.09), 0.0, 1.0,
                       spectra % "green")
    light = g.material(
        "light", (0.0, 0.0, 0.0), 0.0, 1.0,
        "rounded linear-sRGB approximation of the published Cornell Box Data "
        "light emission spectrum (400 nm 0.0, 500 nm 8.0, 600 nm 15.6, "
        "700 nm 18.4); emitted radiance = emissiveFactor x emissiveStrength; "
        "one-sided, emitting towards -Y; baseColor 0 chosen (pure emitter)",
        emissive=(1.0, 0.52, 0.13), emissive_strength=20.7,
        double_sided=False)

    g.mesh_node("floor", *quad(*CB_FLOOR), white)
    g.mesh_node("ceiling", *quad(*CB_CEILING), white)
    lpos, ltris = quad(*CB_LIGHT)
    check_facing("light", lpos, ltris, (0.0, -1.0, 0.0))
    g.mesh_node("light", lpos, ltris, light)
    g.mesh_node("back_wall", *quad(*CB_BACK_WALL), white)
    g.mesh_node("right_wall", *quad(*CB_RIGHT_WALL), green)
    g.mesh_node("left_wall", *quad(*CB_LEFT_WALL), red)
    g.mesh_node("short_block", *quads(CB_SHORT_BLOCK), white)
    g.mesh_node("tall_block", *quads(CB_TALL_BLOCK), white)

    fov = 2.0 * math.degrees(math.atan(12.5 / 35.0))
    cam = camera_json(
        (278.0, 273.0, -800.0), (278.0, 273.0, 0.0), (0.0, 1.0, 0.0),
        fov, 1.0, (512, 512), "from_source_data",
        "Cornell Box Data camera: position (278, 273, -800), direction "
        "(0, 0, 1), up (0, 1, 0), focal length 0.035 m, film 0.025 x 0.025 m",
        "fov_y = 2*atan(12.5/35) in degrees; image_size chosen (the data "
        "gives none). The data's +x points to the camera's left: the red "
        "left_wall (x ~ 550) is on the left of the image.")
    return g, cam


# --------------------------------------------------------------------------
# 2. SPD "balls" (sphereflake)
# --------------------------------------------------------------------------

SPD_REPO = ("erich666/StandardProceduralDatabases @ "
            "3974043f6a1c6aa9ffa29327edbc72adaa75f0f4")


def spd_balls_objset():
    """The 9 unit child directions of SPD balls.c create_objset(): three
    vectors (d,d,0), (d,0,-d), (0,d,-d) with d = 1/sqrt(2), rotated about
    (1,-1,0)/sqrt(2) by asin(2/sqrt(6)), then copied at 0, 120 and 240
    degrees about +Z. Angles enter only through their exact sin/cos."""
    d = 1.0 / math.sqrt(2.0)
    trio = [(d, d, 0.0), (d, 0.0, -d), (0.0, d, -d)]
    axis = normalize((1.0, -1.0, 0.0))
    sin_a = 2.0 / math.sqrt(6.0)
    cos_a = 1.0 / math.sqrt(3.0)  # sqrt(1 - 4/6)
    trio = [rotate(v, axis, cos_a, sin_a) for v in trio]
    z = (0.0, 0.0, 1.0)
    turns = [(1.0, 0.0), (-0.5, math.sqrt(3.0) / 2.0),
             (-0.5, -math.sqrt(3.0) / 2.0)]
    out = []
    for cos_t, sin_t in turns:
        for v in trio:
            out.append(rotate(v, z, cos_t, sin_t))
    return out


def spd_balls_spheres(depth):
    """List of (level, center, radius) as in SPD balls.c output_object():
    root radius 0.5 at the origin growing along +Z; each child has 1/3 of
    its parent's radius and sits at distance (4/3) * parent radius (touching
    it) in the parent's growth direction frame."""
    objset = spd_balls_objset()
    out = []

    def recurse(level, center, radius, direction):
        out.append((level, center, radius))
        if level == depth:
            return
        rot = rotation_between((0.0, 0.0, 1.0), direction)
        dist = radius * (1.0 + 1.0 / 3.0)
        for v in objset:
            w = v if rot is None else rotate(v, *rot)
            child = add(center, scale(w, dist))
            recurse(level + 1, child, radius / 3.0, normalize(w))

    recurse(0, (0.0, 0.0, 0.0), 0.5, (0.0, 0.0, 1.0))
    return out


def scene_spd_balls():
    depth = 2
    g = Gltf("spd_balls",
             "Sphereflake after Eric Haines's Standard Procedural Databases "
             "balls.c (" + SPD_REPO + "), size_factor 2 (91 spheres), "
             "spheres tessellated as icospheres (subdivided twice, one "
             "fixed generic orientation)")
    metal = g.material(
        "flake_metal", (0.9, 0.75, 0.6), 1.0, 0.05,
        "chosen: shiny metal in the spirit of SPD balls.c 'mirrored' surface "
        "(color 1.0 0.9 0.7, Ks 0.5, shine 37)")
    ground = g.material(
        "ground", (0.8, 0.6, 0.264), 0.0, 1.0,
        "SPD balls.c floor: beige color (1.0, 0.75, 0.33) x Kd 0.8, matte")

    # SPD balls.c floor polygon: square of half-size 12 at z = -0.5
    # (wound counter-clockwise seen from +Z).
    gpos, gtris = quad((12.0, 12.0, -0.5), (-12.0, 12.0, -0.5),
                       (-12.0, -12.0, -0.5), (12.0, -12.0, -0.5))
    check_facing("ground", gpos, gtris, (0.0, 0.0, 1.0))
    g.mesh_node("ground", gpos, gtris, ground)

    unit = rotated_icosphere(unit_icosphere(2), FLAKE_ICO_ROT)
    spheres = spd_balls_spheres(depth)
    assert len(spheres) == 91
    for level in range(depth + 1):
        parts = []
        for lv, c, r in spheres:
            if lv != level:
                continue
            p, t = sphere_mesh(c, r, unit)
            check_outward("flake", p, t, c)
            parts.append((p, t))
        pos, tris = merge(parts)
        g.mesh_node("flake_level%d" % level, pos, tris, metal)

    # SPD balls.c light positions, unchanged (the scene has SPD's scale).
    # SPD lights do not fall off with distance and have intensity
    # 1/sqrt(3) each; a glTF point light falls off as 1/d^2, so the
    # intensity is 1/sqrt(3) * |p|^2: same irradiance at the flake centre.
    lights = [(4.0, 3.0, 2.0), (1.0, -4.0, 4.0), (-3.0, 1.0, 5.0)]
    for i, p in enumerate(lights):
        inten = dot(p, p) / math.sqrt(3.0)
        g.point_light(
            "point_light_%d" % i, p, (1.0, 1.0, 1.0), inten,
            "SPD balls.c: light at (%g, %g, %g), intensity 1/sqrt(3) "
            "without distance falloff; glTF intensity = 1/sqrt(3) x %g "
            "(squared distance to the origin)" % (p + (dot(p, p),)))

    cam = camera_json(
        (2.1, 1.3, 1.7), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 45.0, 1.0,
        (512, 512), "computed_default",
        "SPD balls.c: lib_output_viewpoint(from (2.1, 1.3, 1.7), at (0, 0, 0), "
        "up (0, 0, 1), angle 45, aspect 1, hither 0.01, 512 x 512)",
        "SPD's viewpoint kept unchanged (this scene keeps SPD's coordinates); "
        "checked that every sphere vertex of the flake projects inside the "
        "frame. Z is up.")
    return g, cam


# --------------------------------------------------------------------------
# 3. SPD "tetra" (Sierpinski tetrahedron)
# --------------------------------------------------------------------------

INV_SQRT3 = 1.0 / math.sqrt(3.0)
# SPD tetra.c's frame has its "up" along (-1,-1,1)/sqrt(3) (the direction of
# the tetrahedron's apex). Our frame is Z-up: rotate that direction onto +Z
# (about (-1,1,0)/sqrt(2)), then lift by 1/sqrt(3) so the base is at z = 0.
TETRA_UP = normalize((-1.0, -1.0, 1.0))
TETRA_ROT = rotation_between(TETRA_UP, (0.0, 0.0, 1.0))
TETRA_LIFT = (0.0, 0.0, INV_SQRT3)


def tetra_to_world(p):
    w = add(rotate(p, *TETRA_ROT), TETRA_LIFT)
    # snap rounding noise (the base plane is exactly z = 0)
    return tuple(0.0 if abs(c) < 1e-12 else c for c in w)


def tetra_vector_to_world(v):
    return rotate(v, *TETRA_ROT)


def sierpinski(levels):
    """SPD tetra.c create_tetra(): the tetrahedron inscribed in the cube
    centre +- half (corners with x*y*z = +1 in the cube's sign pattern),
    recursively replaced by the 4 half-size tetrahedra at its corners.
    Returns a list of tetrahedra, each 4 corner points (SPD's frame)."""
    out = []

    def recurse(level, center, half):
        if level == 0:
            pts = []
            for sx in (-1.0, 1.0):
                for sy in (-1.0, 1.0):
                    for sz in (-1.0, 1.0):
                        if sx * sy * sz == 1.0:
                            pts.append((center[0] + sx * half,
                                        center[1] + sy * half,
                                        center[2] + sz * half))
            out.append(pts)
            return
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                for sz in (-1.0, 1.0):
                    if sx * sy * sz == 1.0:
                        recurse(level - 1,
                                (center[0] + sx * half / 2.0,
                                 center[1] + sy * half / 2.0,
                                 center[2] + sz * half / 2.0), half / 2.0)

    recurse(levels, (0.0, 0.0, 0.0), 1.0)
    return out


def scene_spd_tetra():
    levels = 4
    g = Gltf("spd_tetra",
             "Sierpinski tetrahedron after Eric Haines's Standard Procedural "
             "Databases tetra.c (" + SPD_REPO + "), 4 levels of recursion "
             "(256 tetrahedra, SPD size_factor 5), rotated to Z-up, on a "
             "mirror ground")
    red = g.material(
        "tetra_red", (1.0, 0.2, 0.2), 0.0, 1.0,
        "SPD tetra.c: color (1.0, 0.2, 0.2), Kd 1.0, Ks 0 (matte)")
    mirror = g.material(
        "ground_mirror", (0.9, 0.9, 0.9), 1.0, 0.02,
        "chosen: mirror-like ground (SPD tetra.c has no ground)")
    lamp = g.material(
        "area_light", (0.0, 0.0, 0.0), 0.0, 1.0,
        "chosen: one-sided emissive quad above the apex, emitting towards -Z; "
        "emitted radiance = emissiveFactor x emissiveStrength",
        emissive=(1.0, 1.0, 1.0), emissive_strength=10.0,
        double_sided=False)

    # SPD face order: (0 1 2), (3 2 1), (2 3 0), (1 0 3); checked outward.
    faces = [(0, 1, 2), (3, 2, 1), (2, 3, 0), (1, 0, 3)]
    pos, tris = [], []
    tets = sierpinski(levels)
    assert len(tets) == 256
    for t in tets:
        base = len(pos)
        world = [tetra_to_world(p) for p in t]
        pos.extend(world)
        c = scale(add(add(world[0], world[1]), add(world[2], world[3])), 0.25)
        local = [(a + base, b + base, cc + base) for a, b, cc in faces]
        check_outward("tetra", pos, local, c)
        tris.extend(local)
    g.mesh_node("tetra", pos, tris, red)

    # ground: 0.01 below the base (z = 0) so that it is not coplanar with
    # the bottom faces of the lowest tetrahedra.
    gz = -0.01
    gpos, gtris = quad((5.0, 5.0, gz), (-5.0, 5.0, gz), (-5.0, -5.0, gz),
                       (5.0, -5.0, gz))
    check_facing("ground", gpos, gtris, (0.0, 0.0, 1.0))
    g.mesh_node("ground", gpos, gtris, mirror)

    # area light: 1.2 x 1.2 quad at z = 3.5 above the apex (z = 4/sqrt(3)),
    # wound so its normal is -Z (emitting downwards).
    lz, h = 3.5, 0.6
    lpos, ltris = quad((-h, -h, lz), (-h, h, lz), (h, h, lz), (h, -h, lz))
    check_facing("area_light", lpos, ltris, (0.0, 0.0, -1.0))
    g.mesh_node("area_light", lpos, ltris, lamp)

    # sun: shines from the direction of SPD tetra.c's point light
    # (2, -18, -5) as seen from the tetrahedron's centre (SPD's origin).
    to_light = normalize(tetra_vector_to_world((2.0, -18.0, -5.0)))
    travel = scale(to_light, -1.0)
    q = quat_from_to((0.0, 0.0, -1.0), travel)
    assert length(sub(quat_rotate(q, (0.0, 0.0, -1.0)), travel)) < 1e-12
    g.directional_light(
        "sun", q, (1.0, 1.0, 1.0), 3.0,
        "SPD tetra.c: point light at (2, -18, -5) (tetrahedron frame), used "
        "here as the direction of a directional light (rotated with the "
        "geometry); intensity 3.0 chosen")

    # camera: SPD tetra.c viewpoint rotated with the geometry, eye pulled
    # back along the view line (x1.15 from the target): SPD's own distance
    # frames the tetrahedron with almost no margin (outermost vertex at
    # 0.96 of the half-frame; 0.83 with this factor).
    eye0 = tetra_to_world((1.022846, -3.177154, -2.174512))
    at = tetra_to_world((-0.004103, -0.004103, 0.216539))
    eye = add(at, scale(sub(eye0, at), 1.15))
    cam = camera_json(
        eye, at, (0.0, 0.0, 1.0), 45.0, 1.0, (512, 512), "computed_default",
        "SPD tetra.c: lib_output_viewpoint(from (1.022846, -3.177154, "
        "-2.174512), at (-0.004103, -0.004103, 0.216539), up (-0.816497, "
        "-0.816497, 0.816497), angle 45, aspect 1, 512 x 512)",
        "SPD's viewpoint transformed with the geometry (rotation taking "
        "(-1,-1,1)/sqrt(3) to +Z, then z + 1/sqrt(3)); the eye is moved "
        "back to 1.15 x its distance from the target, so that every "
        "tetrahedron vertex projects inside the frame with a margin (SPD's "
        "distance puts the outermost vertex at 0.96 of the half-frame). "
        "Z is up.")
    return g, cam


# --------------------------------------------------------------------------
# 4. glass and metal spheres
# --------------------------------------------------------------------------

def scene_glass_spheres():
    g = Gltf("glass_spheres",
             "HRPP test scene (original): glass and metal icospheres on a "
             "floor in front of a back wall, one point light")
    floor_mat = g.material("floor", (0.7, 0.7, 0.7), 0.0, 1.0,
                           "chosen: matte light grey")
    wall_mat = g.material("back_wall", (0.6, 0.65, 0.75), 0.0, 1.0,
                          "chosen: matte light blue-grey")
    glass = g.material(
        "glass", (1.0, 1.0, 1.0), 0.0, 0.0,
        "chosen: clear glass, KHR_materials_transmission 1 + "
        "KHR_materials_ior 1.5; closed mesh wound outwards, one-sided",
        transmission=1.0, ior=1.5, double_sided=False)
    metal = g.material("metal", (0.95, 0.64, 0.54), 1.0, 0.1,
                       "chosen: polished copper-coloured metal")

    # Y up. Floor y = 0, x in [-3, 3], z in [-3, 3]; wound with normal +Y.
    fpos, ftris = quad((-3.0, 0.0, -3.0), (-3.0, 0.0, 3.0),
                       (3.0, 0.0, 3.0), (3.0, 0.0, -3.0))
    check_facing("floor", fpos, ftris, (0.0, 1.0, 0.0))
    g.mesh_node("floor", fpos, ftris, floor_mat)
    # Back wall z = -3, x in [-3, 3], y in [0, 4]; normal +Z (towards camera).
    wpos, wtris = quad((-3.0, 0.0, -3.0), (3.0, 0.0, -3.0),
                       (3.0, 4.0, -3.0), (-3.0, 4.0, -3.0))
    check_facing("back_wall", wpos, wtris, (0.0, 0.0, 1.0))
    g.mesh_node("back_wall", wpos, wtris, wall_mat)

    unit = unit_icosphere(3)
    r = 0.6
    # centres 0.002 above radius height: the spheres clear the floor.
    cg = (-0.75, r + 0.002, -0.4)
    cm = (0.8, r + 0.002, -1.2)
    p, t = sphere_mesh(cg, r, unit)
    check_outward("glass_sphere", p, t, cg)
    g.mesh_node("glass_sphere", p, t, glass)
    p, t = sphere_mesh(cm, r, unit)
    check_outward("metal_sphere", p, t, cm)
    g.mesh_node("metal_sphere", p, t, metal)

    g.point_light("point_light_0", (-1.0, 3.2, 1.5), (1.0, 1.0, 1.0), 30.0,
                  "chosen: point light above and in front of the spheres "
                  "(intensity in glTF candela, 1/d^2 falloff)")

    cam = camera_json(
        (0.0, 1.5, 4.5), (0.0, 0.6, -0.8), (0.0, 1.0, 0.0), 40.0, 1.0,
        (512, 512), "computed_default",
        "computed: in front of the spheres, slightly above, looking at the "
        "midpoint between them",
        "not from an external source; both spheres and the floor/back wall "
        "behind them are in the frame. Y is up.")
    return g, cam


# --------------------------------------------------------------------------
# 5.-7. more SPD models: rings, gears, tree
# --------------------------------------------------------------------------
#
# SPD's generators call cos() and sin() for their geometry. Here every sine
# and cosine comes from sincos_deg() below: a fixed reduction to [-45, 45]
# degrees and fixed-length Taylor series, so + - * / only and the same bits
# on every platform. Line numbers cite the SPD files as listed in SPD_REPO
# (rings.c, gears.c, tree.c, mount.c, lattice.c, shells.c, jacks.c,
# sombrero.c, libvec.c, libply.c and libpr2.c are unchanged in the
# repository's later src/ layout, so the numbers hold there too; libtx.c
# differs in one typedef on line 24, with the same line numbers).

SPD_PI = 3.141592653589793  # SPD def.h:179


def sincos_deg(deg):
    """(sin, cos) of an angle in degrees with + - * / only: reduce to
    r in [-45, 45] degrees plus a quadrant, then Taylor series of 14 terms
    (the error at 45 degrees is below 1e-17). Multiples of 90 degrees are
    exact."""
    d = deg % 360.0
    q = int(round(d / 90.0))
    r = d - 90.0 * q
    x = r * (SPD_PI / 180.0)
    x2 = x * x
    s, term = 0.0, x
    c, cterm = 0.0, 1.0
    for k in range(14):
        s += term
        c += cterm
        term = -term * x2 / ((2 * k + 2) * (2 * k + 3))
        cterm = -cterm * x2 / ((2 * k + 1) * (2 * k + 2))
    q %= 4
    if q == 0:
        return s, c
    if q == 1:
        return c, -s
    if q == 2:
        return -s, -c
    return -c, s


def spd_light_intensity(p, ref, lscale):
    """SPD lights have intensity lscale (1/sqrt(number of lights), e.g.
    rings.c:157-158) and no distance falloff; a glTF point light falls off
    as 1/d^2, so the glTF intensity is lscale x |p - ref|^2: SPD's
    irradiance at the reference point ref."""
    d = sub(p, ref)
    return lscale * dot(d, d)


def perpendicular_frame(a):
    """Unit vectors (u, v) with u x v = a for a unit vector a: u is a x e
    for the coordinate axis e least aligned with a (sqrt only)."""
    k = min(range(3), key=lambda i: (abs(a[i]), i))
    e = tuple(1.0 if i == k else 0.0 for i in range(3))
    u = normalize(cross(a, e))
    return u, cross(a, u)


def unit_circle(n):
    """The n points (cos, sin) of k * 360/n degrees, from sincos_deg."""
    out = []
    for k in range(n):
        s, c = sincos_deg(360.0 * k / n)
        out.append((c, s))
    return out


def cylcone_mesh(base, r0, apex, r1, circle):
    """SPD lib_output_cylcone (an open cone or cylinder: NFF 'c' has no
    caps) from base (radius r0) to apex (radius r1) as a band of
    2 x len(circle) triangles, wound outwards (checked)."""
    axis = normalize(sub(apex, base))
    u, v = perpendicular_frame(axis)
    pos, tris = [], []
    n = len(circle)
    for c, s in circle:
        d = add(scale(u, c), scale(v, s))
        pos.append(add(base, scale(d, r0)))
    for c, s in circle:
        d = add(scale(u, c), scale(v, s))
        pos.append(add(apex, scale(d, r1)))
    for i in range(n):
        j = (i + 1) % n
        tris.append((i, j, n + j))
        tris.append((i, n + j, n + i))
    for t in tris:
        a, b, cc = pos[t[0]], pos[t[1]], pos[t[2]]
        nrm = cross(sub(b, a), sub(cc, a))
        cen = scale(add(add(a, b), cc), 1.0 / 3.0)
        radial = sub(sub(cen, base), scale(axis, dot(sub(cen, base), axis)))
        if dot(nrm, radial) <= 0.0:
            raise AssertionError("cylcone: triangle %s wound inwards" % (t,))
    return pos, tris


def spd_point_lights(g, file, lines, lights, ref, ref_name):
    lscale = 1.0 / math.sqrt(len(lights))
    for i, p in enumerate(lights):
        g.point_light(
            "point_light_%d" % i, p, (1.0, 1.0, 1.0),
            spd_light_intensity(p, ref, lscale),
            "SPD %s:%s: light at (%g, %g, %g), intensity 1/sqrt(%d) without "
            "distance falloff; glTF intensity = 1/sqrt(%d) x %g (squared "
            "distance to %s)" % (file, lines, p[0], p[1], p[2], len(lights),
                                 len(lights), dot(sub(p, ref), sub(p, ref)),
                                 ref_name))


# -- 5. SPD "rings" -----------------------------------------------------------

RINGS_SIZE = 3
RINGS_RADIUS = 0.07412  # rings.c:127, cylinder and sphere radius
RINGS_SIDES = 16        # cylinder tessellation (chosen)


def spd_rings_dodec(minor_radius):
    """rings.c:43-100 create_dodec(): 6 pentagons of 5 points each. The
    first lies in the XY plane (radius 1/(1+minor_radius), points at
    k x 72 degrees); pentagon p = 1..5 is the first rotated about X by
    x_rotation = 2 acos(cos 60 / sin 36) (rings.c:71-72), then about Z by
    (2(p-1)+1) x 36 degrees (rings.c:84), with libvec.c's row-vector
    rotation matrices (libvec.c:135-176, 713-723). cos x_rotation =
    2a^2 - 1 and sin x_rotation = 2a sqrt(1 - a^2) for a = 0.5 / sin 36."""
    sc = 1.0 / (1.0 + minor_radius)
    verts = []
    for k in range(5):
        s, c = sincos_deg(72.0 * k)
        verts.append((sc * c, sc * s, 0.0))
    a = 0.5 / sincos_deg(36.0)[0]
    cx = 2.0 * a * a - 1.0
    sx = 2.0 * a * math.sqrt(1.0 - a * a)
    for p in range(1, 6):
        sz, cz = sincos_deg(36.0 * (2 * (p - 1) + 1))
        for k in range(5):
            x, y, z = verts[k]
            t = (x, y * cx - z * sx, y * sx + z * cx)
            verts.append((t[0] * cz - t[1] * sz, t[0] * sz + t[1] * cz, t[2]))
    return verts


def scene_spd_rings():
    sf = RINGS_SIZE
    r = RINGS_RADIUS
    g = Gltf("spd_rings",
             "Pyramid of interlocking pentagonal rings after Eric Haines's "
             "Standard Procedural Databases rings.c (" + SPD_REPO + "), "
             "size_factor %d (%d ring objects, %d spheres, %d cylinders), "
             "spheres as icospheres (subdivided once), cylinders as open "
             "%d-sided bands" % (sf, sf * (sf + 1) * (2 * sf + 1) // 6,
                                 5 * sf * (sf + 1) * (2 * sf + 1),
                                 5 * sf * (sf + 1) * (2 * sf + 1),
                                 RINGS_SIDES))
    # rings.c:130-138 (SPREAD_OUT 1 <= spread: y_diff = spread, xz_diff 1)
    spread = 1.0 / sincos_deg(22.5)[0]
    y_diff, xz_diff = spread, 1.0
    wall_mat = g.material(
        "wall", (1.0, 1.0, 1.0), 0.0, 1.0,
        "SPD rings.c:168-170: white (1, 1, 1), Kd 1.0, matte")
    names = ["red", "green", "blue", "cyan", "magenta", "yellow"]
    colors = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0),
              (0.0, 1.0, 1.0), (1.0, 0.0, 1.0), (1.0, 1.0, 0.0)]
    ring_mats = []
    for i in range(6):
        ring_mats.append(g.material(
            "ring_" + names[i], scale(colors[i], 0.5), 0.0, 0.5,
            "SPD rings.c:182-187, 207-208: ring %d color (%g, %g, %g) x Kd "
            "0.5 (lib_output_color ka 0, kd 0.5, ks 0.2, ks_spec 0.3, ang "
            "37); roughness 0.5 chosen for the specular part" % (
                (i,) + colors[i])))

    # rings.c:172-179: the wall behind the pyramid, spanning the 45 degree
    # view + 1% (tan 22.5 from sincos_deg).
    eye = (-1.0, -spread, 0.5)  # rings.c:147
    wy = y_diff * (sf + 1)
    s22, c22 = sincos_deg(22.5)
    wx = 1.01 * (wy - eye[1]) * (s22 / c22)
    wall = [(wx + eye[0], wy, wx + eye[2]), (-wx + eye[0], wy, wx + eye[2]),
            (-wx + eye[0], wy, -wx + eye[2]), (wx + eye[0], wy, -wx + eye[2])]
    wpos, wtris = quad(*wall)
    check_facing("wall", wpos, wtris, (0.0, -1.0, 0.0))
    g.mesh_node("wall", wpos, wtris, wall_mat)

    dodec = spd_rings_dodec(r)
    for i in range(30):
        for j in range(i):
            assert length(sub(dodec[i], dodec[j])) > 2.0 * r
    unit = rotated_icosphere(unit_icosphere(1), FLAKE_ICO_ROT)
    circle = unit_circle(RINGS_SIDES)
    parts = [[] for _ in range(6)]
    # rings.c:193-221: layer d (0..sf-1) at y = y_diff (d+1) holds
    # (d+1)^2 objects at x, z = xz_diff (2i - d); each object is 30
    # cylinders (from point e to the previous point of its pentagon) and
    # 30 spheres (at e), all of radius 0.07412.
    for depth in range(sf):
        oy = y_diff * (depth + 1)
        for iz in range(depth + 1):
            oz = xz_diff * (2 * iz - depth)
            for ix in range(depth + 1):
                ox = xz_diff * (2 * ix - depth)
                off = (ox, oy, oz)
                for e in range(30):
                    prev = e + 4 if e % 5 == 0 else e - 1
                    b = add(dodec[e], off)
                    a = add(dodec[prev], off)
                    parts[e // 5].append(cylcone_mesh(b, r, a, r, circle))
                    p, t = sphere_mesh(b, r, unit)
                    check_outward("ring_sphere", p, t, b)
                    parts[e // 5].append((p, t))
    for i in range(6):
        pos, tris = merge(parts[i])
        g.mesh_node("ring_" + names[i], pos, tris, ring_mats[i])

    # rings.c:160-166: three lights; reference point for the glTF
    # intensity: the centre of the pyramid.
    centre = (0.0, y_diff * (sf + 1) / 2.0, 0.0)
    spd_point_lights(g, "rings.c", "161-166",
                     [(3.0, -spread, 3.0), (-4.0, -spread, 1.0),
                      (2.0, -spread, -4.0)], centre,
                     "the pyramid's centre (0, %g, 0)" % centre[1])

    cam = camera_json(
        eye, (eye[0], eye[1] + 1.0, eye[2]), (0.0, 0.0, 1.0), 45.0, 1.0,
        (512, 512), "computed_default",
        "SPD rings.c:147-150: lib_output_viewpoint(from (-1, -spread, 0.5), "
        "at from + (0, 1, 0), up (0, 0, 1), angle 45, aspect 1, 512 x 512), "
        "spread = 1/sin(22.5 degrees) = %.6f" % spread,
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates); the "
        "camera looks along +Y at the pyramid's point, the wall at y = %.6f "
        "fills the frame (1%% margin). Z is up." % wy)
    return g, cam


# -- 6. SPD "gears" -----------------------------------------------------------

GEARS_SIZE = 4
GEARS_TEETH = 36           # gears.c:41
GEARS_OUTER_EDGE = 0.995   # gears.c:48
GEARS_EDGE_DIFF = 0.1      # gears.c:49-50 (1 - INNER_EDGE_RATIO 0.9)
GEARS_DEPTH_RATIO = 0.1    # gears.c:53


def spd_gear_outline(offset_deg, outer_r, inner_r):
    """gears.c:56-76, 96-101: 4 points per tooth at angles gear - 0.19 t,
    gear + 0.19 t (outer radius), gear + 0.3 t, gear + 0.7 t (inner radius)
    for gear = offset + k t, t = 360/TEETH degrees; counter-clockwise about
    +Z around the gear's centre, as (cos, sin) pairs times radius."""
    t = 360.0 / GEARS_TEETH
    out = []
    for k in range(GEARS_TEETH):
        ga = offset_deg + t * k
        for frac, rad in ((-0.19, outer_r), (0.19, outer_r), (0.3, inner_r),
                          (0.7, inner_r)):
            s, c = sincos_deg(ga + frac * t)
            out.append((rad * c, rad * s))
    return out


def spd_gear_mesh(center, outline, thickness):
    """One closed gear: the top polygon at the centre's z (gears.c:96-102),
    the 4 x TEETH side quads down to z - thickness (gears.c:105-114) and the
    bottom polygon (gears.c:117-125: the same outline, as SPD's negated
    angles give, wound the other way). SPD's concave 144-gon faces are fans
    from the centre (every outline point is at a larger angle than the one
    before, so each fan triangle is proper). Wound outwards."""
    n = len(outline)
    cx, cy, cz = center
    bz = cz - thickness
    pos = [(cx + x, cy + y, cz) for x, y in outline]
    pos += [(cx + x, cy + y, bz) for x, y in outline]
    top_c, bot_c = 2 * n, 2 * n + 1
    pos += [(cx, cy, cz), (cx, cy, bz)]
    tris = []
    for i in range(n):
        j = (i + 1) % n
        tris.append((top_c, i, j))                  # top, normal +Z
        tris.append((bot_c, n + j, n + i))          # bottom, normal -Z
        tris.append((i, n + i, n + j))              # side (SPD's quad order)
        tris.append((i, n + j, j))
    for t in tris:
        a, b, c = pos[t[0]], pos[t[1]], pos[t[2]]
        nrm = cross(sub(b, a), sub(c, a))
        if t[0] == top_c:
            ok = nrm[2] > 0.0 and nrm[0] == 0.0 == nrm[1]
        elif t[0] == bot_c:
            ok = nrm[2] < 0.0 and nrm[0] == 0.0 == nrm[1]
        else:
            # a side faces away from the gear's axis at its midpoint
            mid = scale(add(add(a, b), c), 1.0 / 3.0)
            ok = nrm[2] == 0.0 and dot(nrm, sub(mid, center)) > 0.0
        if not ok:
            raise AssertionError("gear: triangle %s wound inwards" % (t,))
    return pos, tris


def scene_spd_gears():
    sf = GEARS_SIZE
    g = Gltf("spd_gears",
             "Grid of meshing gears after Eric Haines's Standard Procedural "
             "Databases gears.c (" + SPD_REPO + "), size_factor %d (%d gears "
             "of %d teeth), gear faces fanned into triangles, on a "
             "reflective ground" % (sf, sf ** 3, GEARS_TEETH))
    ground_mat = g.material(
        "ground", (1.0, 0.85, 0.7), 0.67, 0.1,
        "SPD gears.c:186-187: off-white (1, 0.85, 0.7), Kd 0.3, Ks 0.6, "
        "shine 37 ('reflective', gears.c:4); metallic 0.67 (Ks / (Kd + Ks)) "
        "and roughness 0.1 chosen")
    gpos, gtris = quad((2.0, 2.0, 0.0), (-2.0, 2.0, 0.0), (-2.0, -2.0, 0.0),
                       (2.0, -2.0, 0.0))  # gears.c:188-192
    check_facing("ground", gpos, gtris, (0.0, 0.0, 1.0))
    g.mesh_node("ground", gpos, gtris, ground_mat)

    # gears.c:194-203
    outer_radius = 1.0 / (sf - (sf - 1) * GEARS_EDGE_DIFF / 2.0)
    zero = (-1.0 + outer_radius, -1.0 + outer_radius, 1.0)
    step = outer_radius * (2.0 - GEARS_EDGE_DIFF)
    step_z = -1.0 / sf
    thickness = min(GEARS_DEPTH_RATIO, 1.0 / (2.0 * sf))  # gears.c:232
    outlines = [spd_gear_outline(180.0 * par / GEARS_TEETH,
                                 GEARS_OUTER_EDGE * outer_radius,
                                 (1.0 - GEARS_EDGE_DIFF) * outer_radius)
                for par in (0, 1)]
    for iz in range(sf):
        for iy in range(sf):
            for ix in range(sf):
                center = (zero[0] + ix * step, zero[1] + iy * step,
                          zero[2] + iz * step_z)
                # gears.c:214-222: pseudo-random colour, FRACTION() of
                # non-negative numbers, scaled so the largest is 1
                col = [0.01 + (x - int(x)) for x in (
                    (ix * 3 + iy * 2 + iz + 1) * 5.0 / 7.0,
                    (iy * 3 + iz * 2 + ix + 1) * 3.0 / 7.0,
                    (iz * 3 + ix * 2 + iy + 1) * 2.0 / 7.0)]
                m = max(col)
                col = tuple(x / m for x in col)
                name = "gear_%d_%d_%d" % (ix, iy, iz)
                if (ix * 4 + iy * 2 + iz) % 5 == 0:
                    mat = g.material(
                        name, col, 0.0, 0.0,
                        "SPD gears.c:214-225: colour (%.6f, %.6f, %.6f), Kd "
                        "0.2, Kt 0.8, index of refraction 1.1; "
                        "KHR_materials_transmission 0.8 + KHR_materials_ior "
                        "1.1; closed mesh wound outwards, one-sided" % col,
                        transmission=0.8, ior=1.1, double_sided=False)
                else:
                    mat = g.material(
                        name, col, 0.0, 1.0,
                        "SPD gears.c:214-228: colour (%.6f, %.6f, %.6f), Kd "
                        "1.0, matte" % col)
                # gears.c:231: every other gear is turned half a tooth
                outline = outlines[(ix + iy + iz) % 2]
                pos, tris = spd_gear_mesh(center, outline, thickness)
                g.mesh_node(name, pos, tris, mat)

    spd_point_lights(g, "gears.c", "172-183",
                     [(2.0, 4.0, 4.0), (-2.0, 4.0, 3.0), (2.0, -2.5, 2.5),
                      (-1.0, -4.0, 2.0), (-1.111, -2.121, 2.626)],
                     (0.0, 0.0, 0.5), "the gear block's centre (0, 0, 0.5)")
    cam = camera_json(
        (-1.1, -2.1, 2.6), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 45.0, 1.0,
        (512, 512), "computed_default",
        "SPD gears.c:158-161: lib_output_viewpoint(from (-1.1, -2.1, 2.6), "
        "at (0, 0, 0), up (0, 0, 1), angle 45, aspect 1, 512 x 512)",
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates); "
        "looks down on the 4 x 4 x 4 block of gears from above one corner. "
        "Z is up.")
    return g, cam


# -- 7. SPD "tree" ------------------------------------------------------------

TREE_SIZE = 7
TREE_SIDES = 12  # cone tessellation (chosen)


def mat_mul(a, b):
    """4x4 row-major product as libvec.c:878-890 lib_matrix_multiply."""
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)]
            for i in range(4)]


def mat_point(m, p):
    """libvec.c:713-723 lib_transform_point (row vector times matrix)."""
    return tuple(p[0] * m[0][j] + p[1] * m[1][j] + p[2] * m[2][j] + m[3][j]
                 for j in range(3))


def mat_rot(axis, deg):
    """libvec.c:135-176 lib_create_rotate_matrix, sine and cosine from
    sincos_deg."""
    s, c = sincos_deg(deg)
    m = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
    if axis == 0:
        m[1][1], m[2][2], m[1][2], m[2][1] = c, c, s, -s
    elif axis == 1:
        m[0][0], m[2][2], m[2][0], m[0][2] = c, c, s, -s
    else:
        m[0][0], m[1][1], m[0][1], m[1][0] = c, c, s, -s
    return m


def spd_tree_branches(depth):
    """tree.c:48-130: list of (base, base radius, apex, apex radius). Branch
    matrices Rst_i = Rx(angle_i) Rz(divergence_i) S(contraction_i) with the
    translation (0, 0, 1) (tree.c:97-125); angles 40 and 25 degrees,
    divergences 90 and 230 degrees, contractions 0.65 and 0.70; each child
    matrix is Rst_i x parent (tree.c:80); branch width 0.15 x scale, apex
    width 0.67 x base width, child scale 0.67 x parent's (tree.c:38-44,
    62-81)."""
    rst = []
    for angle, div, contr in ((40.0, 90.0, 0.65), (25.0, 230.0, 0.70)):
        rot = mat_mul(mat_rot(0, angle), mat_rot(2, div))
        st = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
        st[0][0] = st[1][1] = st[2][2] = contr
        st[3][2] = 1.0
        rst.append(mat_mul(rot, st))
    out = []

    def grow(mx, sc, d):
        base = mat_point(mx, (0.0, 0.0, 0.0))
        apex = mat_point(mx, (0.0, 0.0, 1.0))
        rb = sc * 0.15
        out.append((base, rb, apex, rb * 0.67))
        if d > 0:
            for i in range(2):
                grow(mat_mul(rst[i], mx), sc * 0.67, d - 1)

    ident = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
    grow(ident, 1.0, depth)
    return out


def scene_spd_tree():
    sf = TREE_SIZE
    g = Gltf("spd_tree",
             "Branching tree (Aono and Kunii) after Eric Haines's Standard "
             "Procedural Databases tree.c (" + SPD_REPO + "), size_factor %d "
             "(%d cones and spheres), cones as open %d-sided bands, spheres "
             "as icospheres (subdivided once), on a field" % (
                 sf, 2 ** (sf + 1) - 1, TREE_SIDES))
    field_mat = g.material("field", (0.2, 0.7, 0.2), 0.0, 1.0,
                           "SPD tree.c:190-191: green (0.2, 0.7, 0.2), "
                           "Kd 1.0, matte")
    tree_mat = g.material("tree", (0.55, 0.4, 0.2), 0.0, 1.0,
                          "SPD tree.c:199-200: brown (0.55, 0.4, 0.2), "
                          "Kd 1.0, matte")
    fpos, ftris = quad((50.0, 50.0, 0.0), (-50.0, 50.0, 0.0),
                       (-50.0, -50.0, 0.0), (50.0, -50.0, 0.0))  # tree.c:192
    check_facing("field", fpos, ftris, (0.0, 0.0, 1.0))
    g.mesh_node("field", fpos, ftris, field_mat)

    branches = spd_tree_branches(sf)
    assert len(branches) == 2 ** (sf + 1) - 1
    unit = rotated_icosphere(unit_icosphere(1), FLAKE_ICO_ROT)
    circle = unit_circle(TREE_SIDES)
    cones, spheres = [], []
    for base, rb, apex, ra in branches:
        cones.append(cylcone_mesh(base, rb, apex, ra, circle))
        p, t = sphere_mesh(apex, ra, unit)   # tree.c:72: sphere at the apex
        check_outward("tree_sphere", p, t, apex)
        spheres.append((p, t))
    g.mesh_node("branches", *merge(cones), tree_mat)
    g.mesh_node("joints", *merge(spheres), tree_mat)

    spd_point_lights(g, "tree.c", "174-187",
                     [(-5.0, 5.0, 50.0), (30.0, -30.0, 30.0),
                      (-40.0, -30.0, 20.0), (10.0, 30.0, 40.0),
                      (-30.0, 40.0, 10.0), (50.0, 25.0, 20.0),
                      (-10.0, -60.0, 30.0)],
                     (0.0, 0.0, 1.5), "the camera's target (0, 0, 1.5)")
    cam = camera_json(
        (4.5, 0.4, 2.0), (0.0, 0.0, 1.5), (0.0, 0.0, 1.0), 45.0, 1.0,
        (512, 512), "computed_default",
        "SPD tree.c:160-163: lib_output_viewpoint(from (4.5, 0.4, 2), at "
        "(0, 0, 1.5), up (0, 0, 1), angle 45, aspect 1, 512 x 512)",
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates); the "
        "tree stands at the origin on the field. Z is up.")
    return g, cam


# -- 8. SPD "mount" -----------------------------------------------------------

MOUNT_SIZE = 6         # mount.c:41 (SPD's default): 2 x 4^6 triangles
MOUNT_NO = 21          # mount.c:55
MOUNT_ICO = 3          # sphere tessellation (chosen)
SPD_LN2 = 0.6931471805599453  # ln 2 rounded to double
# mount.c:287-288: ratio = 2 / exp(ln 2 / (FRACTAL_DIMENSION 2.2 - 1)) =
# 2^(1/6), Roughness = sqrt(ratio^2 - 1) = sqrt(2^(1/3) - 1); 2^(1/3)
# rounded to double (its cube is 2.0 in double arithmetic).
MOUNT_CBRT2 = 1.2599210498948732


def spd_log(x):
    """Natural logarithm with + - * / only (math.frexp is exact): x =
    m 2^e with m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh((m-1)/(m+1)) as a
    series of 24 terms (|t| < 0.172, error below 1e-17)."""
    m, e = math.frexp(x)
    if m < 0.7071067811865476:
        m, e = 2.0 * m, e - 1
    t = (m - 1.0) / (m + 1.0)
    t2 = t * t
    s, p = 0.0, t
    for k in range(24):
        s += p / (2 * k + 1)
        p *= t2
    return 2.0 * s + e * SPD_LN2


def spd_gauss_rand(iseed):
    """libvec.c:992-1024 lib_gauss_rand (Numerical Recipes' GASDEV with a
    linear congruential generator), the logarithm from spd_log."""
    ix2 = iseed
    while True:
        ix1 = (28411 + ix2 * 8121) % 134456
        ix2 = (28411 + ix1 * 8121) % 134456
        v1 = ix1 * 2.0 * 1.0 / 134456 - 1.0
        v2 = ix2 * 2.0 * 1.0 / 134456 - 1.0
        r = v1 * v1 + v2 * v2
        if r < 1.0:
            break
    return v1 * math.sqrt(-2.0 * spd_log(r) / r)


def spd_mount_hash(a, b, c):
    """mount.c:67-69: SPD's original ('faulty') hash_rand, used for the
    published image (mount.c:6-12)."""
    return ((a << (23 - c)) + (b << (15 - c)) + (a << (7 - c))) & 0xFFFF


def spd_mount_heights(sf):
    """mount.c:138-225 grow_mountain: Carpenter's midpoint subdivision of
    the square [-1, 1]^2 (corners at height 0) down to 2^sf cells a side.
    Returns ({(i, j): z} for the (2^sf + 1)^2 grid points, [cells (i, j) in
    SPD's output order]). A point shared by two cells gets its height from
    the same hash and the same two parents in both, which the script
    asserts."""
    n = 1 << sf
    rough = math.sqrt(MOUNT_CBRT2 - 1.0)
    z = {}
    cells = []

    def put(key, val):
        if key in z and z[key] != val:
            raise AssertionError("mount: point %s has two heights" % (key,))
        z[key] = val

    def grow(width, x, y, ll, lr, ur, ul):
        if width == 1:
            put((x, y), ll)
            put((x + 1, y), lr)
            put((x + 1, y + 1), ur)
            put((x, y + 1), ul)
            cells.append((x, y))
            return
        h = width >> 1
        rise = h * 2.0 / n * rough  # mount.c:187-188

        def g(a, b):
            return spd_gauss_rand(MOUNT_NO + spd_mount_hash(a, b, sf))
        lower = (ll + lr) / 2.0 + rise * g(x + h, y)
        right = (lr + ur) / 2.0 + rise * g(x + width, y + h)
        upper = (ur + ul) / 2.0 + rise * g(x + h, y + width)
        left = (ul + ll) / 2.0 + rise * g(x, y + h)
        middle = ((ll + lr + ur + ul) / 4.0
                  + 1.4142136 * rise * g(x + h, y + h))
        grow(h, x, y, ll, lower, middle, left)
        grow(h, x + h, y, lower, lr, right, middle)
        grow(h, x + h, y + h, middle, right, ur, upper)
        grow(h, x, y + h, left, middle, upper, ul)

    grow(n, 0, 0, 0.0, 0.0, 0.0, 0.0)
    return z, cells


def spd_mount_spheres(center, radius):
    """mount.c:101-132 create_spheres: one sphere at center + (0, 0,
    r sqrt(3/2)), three more at that offset rotated about (1, 1, 0)/sqrt 2
    by acos(-1/3) (cos -1/3, sin sqrt(8)/3, libvec.c:304-338) and then
    about Z by 0, 120 and 240 degrees (libvec.c:135-176, 677-689)."""
    pt = (0.0, 0.0, radius * math.sqrt(3.0 / 2.0))
    out = [add(center, pt)]
    a = normalize((1.0, 1.0, 0.0))
    c, s = -1.0 / 3.0, math.sqrt(8.0) / 3.0
    omc = 1.0 - c
    mx = [[a[0] * a[0] + (1.0 - a[0] * a[0]) * c,
           a[0] * a[1] * omc + a[2] * s, a[0] * a[2] * omc - a[1] * s],
          [a[0] * a[1] * omc - a[2] * s,
           a[1] * a[1] + (1.0 - a[1] * a[1]) * c,
           a[1] * a[2] * omc + a[0] * s],
          [a[0] * a[2] * omc + a[1] * s, a[1] * a[2] * omc - a[0] * s,
           a[2] * a[2] + (1.0 - a[2] * a[2]) * c]]
    new_pt = tuple(sum(pt[k] * mx[k][j] for k in range(3)) for j in range(3))
    for i in range(3):
        rz = mat_rot(2, 120.0 * i)
        out.append(add(center, tuple(sum(new_pt[k] * rz[k][j]
                                         for k in range(3))
                                     for j in range(3))))
    return out


def scene_spd_mount():
    sf = MOUNT_SIZE
    g = Gltf("spd_mount",
             "Fractal mountain with a pyramid of 4 glass spheres after Eric "
             "Haines's Standard Procedural Databases mount.c (" + SPD_REPO +
             "), size_factor %d (%d triangles, SPD's original hash), "
             "spheres as icospheres (subdivided %d times)" % (
                 sf, 2 * 4 ** sf, MOUNT_ICO))
    glass_mat = g.material(
        "crystal", (1.0, 1.0, 1.0), 0.0, 0.0,
        "SPD mount.c:273-275: clear white (1, 1, 1), Kd 0.1, Ks 0.1, Kt 0.9, "
        "index of refraction 1.5; KHR_materials_transmission 0.9 + "
        "KHR_materials_ior 1.5, roughness 0; closed meshes wound outwards, "
        "one-sided", transmission=0.9, ior=1.5, double_sided=False)
    mount_mat = g.material(
        "mountain", (0.5, 0.45, 0.35), 0.0, 1.0,
        "SPD mount.c:281-283: grey (0.5, 0.45, 0.35), Kd 1.0, matte")

    # mount.c:278-279: the pyramid's base centre and sphere radius
    centre, radius = (-0.8, 0.8, 1.0), 0.17
    unit = rotated_icosphere(unit_icosphere(MOUNT_ICO), FLAKE_ICO_ROT)
    spheres = []
    for c in spd_mount_spheres(centre, radius):
        p, t = sphere_mesh(c, radius, unit)
        check_outward("mount_sphere", p, t, c)
        spheres.append((p, t))
    g.mesh_node("crystal_spheres", *merge(spheres), glass_mat)

    # mount.c:156-183: each cell (x, y) gives the triangles (ll, lr, ur)
    # and (ur, ul, ll) at X_CORNER + x WIDTH / 2^sf (mount.c:57-60)
    n = 1 << sf
    heights, cells = spd_mount_heights(sf)
    index = {}
    pos, tris = [], []

    def vid(i, j):
        if (i, j) not in index:
            index[(i, j)] = len(pos)
            pos.append((-1.0 + i * 2.0 / n, -1.0 + j * 2.0 / n,
                        heights[(i, j)]))
        return index[(i, j)]
    for x, y in cells:
        ll, lr = vid(x, y), vid(x + 1, y)
        ur, ul = vid(x + 1, y + 1), vid(x, y + 1)
        tris.append((ll, lr, ur))
        tris.append((ur, ul, ll))
    assert len(tris) == 2 * 4 ** sf and len(pos) == (n + 1) ** 2
    for t in tris:
        a, b, c = pos[t[0]], pos[t[1]], pos[t[2]]
        assert cross(sub(b, a), sub(c, a))[2] > 0.0  # faces up
    g.mesh_node("mountain", pos, tris, mount_mat)

    # mount.c:266-271: one light, intensity 1 (1/sqrt(1)); reference
    # point: the camera's target (0, 0, 0)
    spd_point_lights(g, "mount.c", "266-271", [(-100.0, -100.0, 100.0)],
                     (0.0, 0.0, 0.0), "the camera's target (0, 0, 0)")
    cam = camera_json(
        (-1.6, 1.6, 1.7), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 45.0, 1.0,
        (512, 512), "computed_default",
        "SPD mount.c:255-259: lib_output_viewpoint(from (-1.6, 1.6, 1.7), "
        "at (0, 0, 0), up (0, 0, 1), angle 45, aspect 1, 512 x 512)",
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates); "
        "looks down on the mountain over the crystal spheres. Z is up.")
    return g, cam


# -- 9. SPD "lattice" ---------------------------------------------------------

LATTICE_SIZE = 5    # lattice.c:31 default 12
LATTICE_SIDES = 12  # cylinder tessellation (chosen)


def scene_spd_lattice():
    sf = LATTICE_SIZE
    g = Gltf("spd_lattice",
             "Cubic lattice of shiny spheres joined by matte cylinders after "
             "Antonio Costa's lattice.c in Eric Haines's Standard Procedural "
             "Databases (" + SPD_REPO + "), size_factor %d (%d spheres, %d "
             "cylinders), spheres as icospheres (subdivided once), cylinders "
             "as open %d-sided bands" % (sf, (sf + 1) ** 3,
                                         3 * sf * (sf + 1) ** 2,
                                         LATTICE_SIDES))
    sphere_mat = g.material(
        "sphere", (0.9, 0.9, 0.9), 0.5, 0.1,
        "SPD lattice.c:113-115: white (0.9, 0.9, 0.9), Kd 0.5, Ks 0.5, shine "
        "37 ('shiny spheres', lattice.c:2); metallic 0.5 (Ks / (Kd + Ks)) and "
        "roughness 0.1 chosen")
    axis_names = ["x", "y", "z"]
    axis_cols = [(0.9, 0.1, 0.1), (0.1, 0.9, 0.1), (0.1, 0.1, 0.9)]
    cyl_mats = []
    axis_lines = ["121-123", "131-133", "142-144"]
    for k in range(3):
        cyl_mats.append(g.material(
            "cylinder_" + axis_names[k], scale(axis_cols[k], 0.99), 0.0, 1.0,
            "SPD lattice.c:%s: colour (%g, %g, %g) x Kd 0.99 (Ka 0.1), "
            "matte" % ((axis_lines[k],) + axis_cols[k])))

    # lattice.c:41-46, 70-71
    inv = 1.0 / sf
    radius1 = 0.25 / sf
    radius2 = 0.0625 / sf
    delta = (radius1 * (1.0 - math.sqrt(0.0625 / 0.25))) * 0.99
    unit = rotated_icosphere(unit_icosphere(1), FLAKE_ICO_ROT)
    circle = unit_circle(LATTICE_SIDES)
    spheres = []
    cyls = [[], [], []]
    # lattice.c:102-153: a sphere of radius1 at each grid point (x, y, z)/sf
    # and a cylinder of radius2 towards the next point along each axis, its
    # ends delta inside the two spheres
    for x in range(sf + 1):
        x0 = x / sf
        for y in range(sf + 1):
            y0 = y / sf
            for z in range(sf + 1):
                z0 = z / sf
                c = (x0, y0, z0)
                p, t = sphere_mesh(c, radius1, unit)
                check_outward("lattice_sphere", p, t, c)
                spheres.append((p, t))
                for k, last in enumerate((x, y, z)):
                    if last == sf:
                        continue
                    a = list(c)
                    b = list(c)
                    a[k] = c[k] + delta
                    b[k] = c[k] + inv - delta
                    cyls[k].append(cylcone_mesh(tuple(a), radius2, tuple(b),
                                                radius2, circle))
    assert len(spheres) == (sf + 1) ** 3
    assert sum(len(c) for c in cyls) == 3 * sf * (sf + 1) ** 2
    g.mesh_node("spheres", *merge(spheres), sphere_mat)
    for k in range(3):
        g.mesh_node("cylinders_" + axis_names[k], *merge(cyls[k]),
                    cyl_mats[k])

    # lattice.c:87-100: six lights, one beyond each face of the unit cube;
    # reference point: the lattice's centre (0.5, 0.5, 0.5)
    spd_point_lights(g, "lattice.c", "87-100",
                     [(2.0, 0.5, 0.5), (-1.0, 0.5, 0.5), (0.5, 2.0, 0.5),
                      (0.5, -1.0, 0.5), (0.5, 0.5, 2.0), (0.5, 0.5, -1.0)],
                     (0.5, 0.5, 0.5), "the lattice's centre (0.5, 0.5, 0.5)")
    # lattice.c:79-84
    ex = ((sf >> 1) + 0.5) * inv
    eye = (ex, 1.0, 1.0 - 1.0 / (sf << 1))
    target = (ex, -1.0, -1.0 - 1.0 / (sf << 1))
    cam = camera_json(
        eye, target, (0.2, 1.0, 0.0), 60.0, 1.0, (512, 512),
        "computed_default",
        "SPD lattice.c:79-84: lib_output_viewpoint(from ((sf >> 1) + 0.5) / "
        "sf, 1, 1 - 1 / (2 sf)), at (((sf >> 1) + 0.5) / sf, -1, -1 - 1 / "
        "(2 sf)), up (0.2, 1, 0), angle 60, aspect 1, 512 x 512) for sf = %d"
        % sf,
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates); the "
        "eye is at the lattice's top back edge, looking diagonally down "
        "through it. Y is roughly up (SPD's up vector (0.2, 1, 0)).")
    return g, cam


# -- 10. SPD "shells" ---------------------------------------------------------

SHELLS_SIZE = 1  # shells.c:36 default 5


def spd_exp(x):
    """e^x with + - * / only (math.ldexp is exact): x = n ln 2 + f with
    |f| <= ln 2 / 2, e^f as a Taylor series of 22 terms."""
    n = int(round(x / SPD_LN2))
    f = x - n * SPD_LN2
    s, term = 0.0, 1.0
    for k in range(22):
        s += term
        term = term * f / (k + 1)
    return math.ldexp(s, n)


def scene_spd_shells():
    sf = SHELLS_SIZE
    steps = 180 * 2 ** sf  # shells.c:220
    lo, hi = -steps * 2 // 3, steps // 3
    g = Gltf("spd_shells",
             "Pickover's sea shell of overlapping spheres after Eric Haines's "
             "Standard Procedural Databases shells.c (" + SPD_REPO + "), "
             "size_factor %d (%d spheres), spheres as icospheres (subdivided "
             "once)" % (sf, hi - lo + 1))
    mat = g.material(
        "shell", scale((1.0, 0.8, 0.4), 0.8), 0.0, 0.5,
        "SPD shells.c:217-218: colour (1, 0.8, 0.4) x Kd 0.8 (ks 0.2, "
        "ks_spec 0.5, ang 10); roughness 0.5 chosen for the specular part")
    # shells.c:48-52, 220-237 with SPD's defaults gamma 1, alpha 0, beta -2,
    # a 0.15, k 1: sphere i (-2 steps/3 .. steps/3) at angle 18 pi i / steps
    # (= 9 i degrees for size factor 1), r = e^(0.15 angle), centre
    # (r sin angle, r cos angle, -2 r), radius r
    unit = rotated_icosphere(unit_icosphere(1), FLAKE_ICO_ROT)
    spheres = []
    for i in range(lo, hi + 1):
        angle = 3.0 * 6.0 * SPD_PI * i / steps
        r = 1.0 * spd_exp(0.15 * angle)
        s, c = sincos_deg(3.0 * 6.0 * 180.0 * i / steps)
        centre = (r * s, r * c, -2.0 * r)
        p, t = sphere_mesh(centre, r / 1.0, unit)
        check_outward("shell_sphere", p, t, centre)
        spheres.append((p, t))
    # shells.c:19-27 counts 180 x 2^sf spheres; the loop (shells.c:221)
    # includes both ends, so it outputs one more
    assert len(spheres) == steps + 1
    g.mesh_node("shell", *merge(spheres), mat)

    # shells.c:212-214: one light, intensity 1; reference point: the
    # camera's target
    target = (0.0, 8.0, -15.0)
    spd_point_lights(g, "shells.c", "212-214", [(-100.0, -100.0, 100.0)],
                     target, "the camera's target (0, 8, -15)")
    cam = camera_json(
        (-6.0, -60.0, 35.0), target, (0.0, 0.0, 1.0), 45.0, 1.0,
        (512, 512), "computed_default",
        "SPD shells.c:206-210: lib_output_viewpoint(from (-6, -60, 35), at "
        "(0, 8, -15), up (0, 0, 1), angle 45, aspect 1, 512 x 512)",
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates); "
        "looks down on the shell, whose spheres grow from radius 0.0035 at "
        "its tip to 16.9 at its mouth. Z is up.")
    return g, cam


# -- 11. SPD "jacks" ----------------------------------------------------------

JACKS_SIZE = 3    # jacks.c:21 default 1 (a single jack)
JACKS_SIDES = 16  # cylinder tessellation (chosen)


def mat_scale(s):
    """libvec.c:357-371 lib_create_scale_matrix for a uniform scale s."""
    m = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
    m[0][0] = m[1][1] = m[2][2] = s
    return m


def mat_translate(t):
    """libvec.c:341-354 lib_create_translate_matrix (translation in row
    3)."""
    m = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
    m[3][0], m[3][1], m[3][2] = t
    return m


def spd_jacks_objects(depth):
    """jacks.c:39-113: (matrix, uniform scale) of every jack. libtx.c:439-480
    applies each new transform before the current one (current = new x
    current, row vectors); the root is Rx(-30) then Ry(-20) (jacks.c:170-
    171), so current = Ry(-20) Rx(-30); a jack is drawn with S(0.75) x
    current (jacks.c:46-50); each of the 8 children at (+-0.5, +-0.5,
    +-0.5) has S(0.5) T(i, j, k) x current (jacks.c:98-111), down to
    size_factor levels."""
    root = mat_mul(mat_rot(1, -20.0), mat_rot(0, -30.0))
    out = []

    def rec(d, cur, sc):
        out.append((mat_mul(mat_scale(0.75), cur), sc * 0.75))
        if d < depth:
            for i in (-0.5, 0.5):
                for j in (-0.5, 0.5):
                    for k in (-0.5, 0.5):
                        m = mat_mul(mat_translate((i, j, k)), cur)
                        rec(d + 1, mat_mul(mat_scale(0.5), m), sc * 0.5)

    rec(1, root, 1.0)
    return out


def scene_spd_jacks():
    sf = JACKS_SIZE
    njacks = sum(8 ** d for d in range(sf))
    g = Gltf("spd_jacks",
             "Recursive jacks (Alexander Enzmann) after Eric Haines's "
             "Standard Procedural Databases jacks.c (" + SPD_REPO + "), "
             "size_factor %d (%d jacks of 3 cylinders and 6 spheres), "
             "spheres as icospheres (subdivided once), cylinders as open "
             "%d-sided bands" % (sf, njacks, JACKS_SIDES))
    pink = (0.737, 0.561, 0.561)  # jacks.c:32
    mat = g.material(
        "jack", scale(pink, 0.7), 0.5, 0.2,
        "SPD jacks.c:32, 173: pink (0.737, 0.561, 0.561) x Kd 0.7 (Ka 0.1, "
        "Ks 0.7, ks_spec 0.4, shine 20); metallic 0.5 (Ks / (Kd + Ks)) and "
        "roughness 0.2 chosen")
    unit = rotated_icosphere(unit_icosphere(1), FLAKE_ICO_ROT)
    circle = unit_circle(JACKS_SIDES)
    cyls, spheres = [], []
    axes = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
    jacks = spd_jacks_objects(sf)
    assert len(jacks) == njacks
    for m, sc in jacks:
        # jacks.c:56-79: cylinders of radius 0.1 from -axis to +axis, and
        # spheres of radius 0.2 at +X, +Y, +Z, -X, -Y, -Z; NFF output
        # transforms the points and scales the radii (libpr2.c:1460-1466)
        for a in axes:
            cyls.append(cylcone_mesh(mat_point(m, scale(a, -1.0)), 0.1 * sc,
                                     mat_point(m, a), 0.1 * sc, circle))
        for sign in (1.0, -1.0):
            for a in axes:
                c = mat_point(m, scale(a, sign))
                p, t = sphere_mesh(c, 0.2 * sc, unit)
                check_outward("jack_sphere", p, t, c)
                spheres.append((p, t))
    g.mesh_node("jack_cylinders", *merge(cyls), mat)
    g.mesh_node("jack_spheres", *merge(spheres), mat)

    # jacks.c:151-156: one light, intensity 1; reference point: the
    # camera's target (0, 0, 0)
    spd_point_lights(g, "jacks.c", "151-156", [(-10.0, 3.0, -20.0)],
                     (0.0, 0.0, 0.0), "the camera's target (0, 0, 0)")
    cam = camera_json(
        (0.0, 0.0, -8.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0), 25.0, 1.0,
        (256, 256), "computed_default",
        "SPD jacks.c:141-145: lib_output_viewpoint(from (0, 0, -8), at "
        "(0, 0, 0), up (0, 1, 0), angle 25, aspect 1, 256 x 256)",
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates); "
        "looks along +Z at the rotated jacks, which float without a ground. "
        "Y is up.")
    return g, cam


# -- 12. SPD "sombrero" -------------------------------------------------------

SOMBRERO_SIZE = 2  # sombrero.c:21 default 1 (32 x 32 points)


def spd_sombrero_data(n, x0, x1, y0, y1):
    """sombrero.c:28-70 create_sombrero: n x n float32 heights
    c cos(2 pi a rho) e^(-b rho) / 3 with a = b = 1, c = 3, SPD's
    two_pi_a = 2 x 3.14159265358 and rho = sqrt(x^2 + y^2); x and y step
    from x0, y0 by (x1 - x0)/n by repeated addition, as in SPD. The cosine
    comes from sincos_deg (the angle converted to degrees) and the
    exponential from spd_exp."""
    two_pi_a = 2.0 * 3.14159265358 * 1.0
    dx = (x1 - x0) / n
    dy = (y1 - y0) / n
    data = []
    y = y0
    for _i in range(n):
        row = []
        x = x0
        for _j in range(n):
            rho = math.sqrt(x * x + y * y)
            c = sincos_deg(two_pi_a * rho * (180.0 / SPD_PI))[1]
            row.append(f32(3.0 * c * spd_exp(-1.0 * rho) / 3.0))
            x += dx
        data.append(row)
        y += dy
    return data


def scene_spd_sombrero():
    sf = SOMBRERO_SIZE
    n = 32 * (1 << (sf - 1))  # sombrero.c:122
    g = Gltf("spd_sombrero",
             "Sombrero height field (Alexander Enzmann) after Eric Haines's "
             "Standard Procedural Databases sombrero.c (" + SPD_REPO + "), "
             "size_factor %d (%d x %d heights, %d triangles as SPD's "
             "polygon output)" % (sf, n, n, 2 * (n - 1) ** 2))
    mat = g.material(
        "shiny_red", scale((1.0, 0.1, 0.1), 0.8), 0.0, 0.5,
        "SPD sombrero.c:117-119: 'shiny_red' (1, 0.1, 0.1) x Kd 0.8 (Ka 0.1, "
        "ks_spec 0.5, shine 40); roughness 0.5 chosen for the highlight")
    data = spd_sombrero_data(n, -4.0, 4.0, -4.0, 4.0)  # sombrero.c:124
    # libply.c:282-320 lib_output_polygon_height with sombrero.c:125's
    # x -4..4, y -3..3, z -4..4: point (i, j) at (x0 + j xdelta,
    # y0 + data[i][j], z0 + i zdelta), per cell the triangles
    # ((i,j), (i+1,j+1), (i,j+1)) and ((i,j), (i+1,j), (i+1,j+1)), facing +Y
    x0, x1, y0, z0, z1 = -4.0, 4.0, -3.0, -4.0, 4.0
    xd = (x1 - x0) / (n - 1)
    zd = (z1 - z0) / (n - 1)
    pos = [(x0 + j * xd, y0 + data[i][j], z0 + i * zd)
           for i in range(n) for j in range(n)]
    tris = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b = i * n + j, i * n + j + 1
            c, d = (i + 1) * n + j, (i + 1) * n + j + 1
            tris.append((a, d, b))
            tris.append((a, c, d))
    assert len(tris) == 2 * (n - 1) ** 2
    for t in tris:
        p0, p1, p2 = pos[t[0]], pos[t[1]], pos[t[2]]
        assert cross(sub(p1, p0), sub(p2, p0))[1] > 0.0  # faces +Y
    g.mesh_node("sombrero", pos, tris, mat)

    # sombrero.c:109-115: one light, intensity 1; reference point: the
    # camera's target (0, 0, 0)
    spd_point_lights(g, "sombrero.c", "109-115", [(10.0, 10.0, -10.0)],
                     (0.0, 0.0, 0.0), "the camera's target (0, 0, 0)")
    cam = camera_json(
        (0.0, 5.0, -8.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 40.0, 1.0,
        (512, 512), "computed_default",
        "SPD sombrero.c:99-103: lib_output_viewpoint(from (0, 5, -8), at "
        "(0, 0, 0), up (0, 0, 1), angle 40, aspect 1, 512 x 512)",
        "SPD's viewpoint unchanged (the scene keeps SPD's coordinates): the "
        "height field's heights run along Y, while SPD's up vector is Z, so "
        "the image's up is the component of (0, 0, 1) across the view, "
        "mostly +Y.")
    return g, cam


# --------------------------------------------------------------------------
# driver
# --------------------------------------------------------------------------

SCENES = [
    ("cornell_box", scene_cornell_box),
    ("spd_balls", scene_spd_balls),
    ("spd_tetra", scene_spd_tetra),
    ("glass_spheres", scene_glass_spheres),
    ("spd_rings", scene_spd_rings),
    ("spd_gears", scene_spd_gears),
    ("spd_tree", scene_spd_tree),
    ("spd_mount", scene_spd_mount),
    ("spd_lattice", scene_spd_lattice),
    ("spd_shells", scene_spd_shells),
    ("spd_jacks", scene_spd_jacks),
    ("spd_sombrero", scene_spd_sombrero),
]


def build_all():
    """Return a list of (name, gltf, {filename: bytes})."""
    out = []
    for name, fn in SCENES:
        g, cam = fn()
        files = {name + ".glb": g.glb(), name + ".camera.json": cam}
        out.append((name, g, files))
    return out


def fmt(v):
    return "(" + ", ".join("%.6g" % x for x in v) + ")"


def main(argv=None):
    here = Path(__file__).resolve().parent
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=here,
                    help="output folder (default: %(default)s)")
    ap.add_argument("--check", action="store_true",
                    help="compare freshly generated bytes with the files in "
                         "the script's folder instead of writing")
    args = ap.parse_args(argv)

    built = build_all()
    if args.check:
        bad = 0
        count = 0
        for _name, _g, files in built:
            for fname, data in files.items():
                count += 1
                path = here / fname
                if not path.is_file():
                    print("missing: %s" % path)
                    bad += 1
                elif path.read_bytes() != data:
                    print("differs: %s (sha256 on disk %s, generated %s)" % (
                        path, hashlib.sha256(path.read_bytes()).hexdigest(),
                        hashlib.sha256(data).hexdigest()))
                    bad += 1
        if bad:
            print("scenes: %d of %d files differ or are missing" % (bad, count))
            return 1
        print("scenes: %d files identical" % count)
        return 0

    args.out.mkdir(parents=True, exist_ok=True)
    for name, g, files in built:
        for fname, data in files.items():
            write_atomic(args.out / fname, data)
        glb = files[name + ".glb"]
        print("%-14s triangles %6d  vertices %6d  bbox %s - %s  %d bytes  "
              "sha256 %s" % (name, g.triangles, g.vertices, fmt(g.bbox_min),
                             fmt(g.bbox_max), len(glb),
                             hashlib.sha256(glb).hexdigest()[:16]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
