#!/usr/bin/env python3
"""Every documented error path of the `hrpp` tool, data-driven: each case writes a bad input
(malformed scene, camera sidecar or ray stream) or passes a bad option, runs the tool, and checks
that it exits with the documented code (2: bad input) within a time limit, that its error message
matches, and that nothing it printed holds a NaN or infinite figure. The valid-range cases also
run `info` and `check-embree` on scenes at the range's edges (exit 0 or 1, no NaN printed).

  tool_errors.py HRPP_BINARY [--list]

Exit status 0 when every case passes, 1 otherwise. ctest runs it as `tool.errors`.
"""
import base64
import json
import os
import re
import struct
import subprocess
import sys
import tempfile

# ---- input builders -----------------------------------------------------------------------------

QUAD = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
QUAD_IDX = [0, 1, 2, 0, 2, 3]


def gltf(positions=QUAD, indices=QUAD_IDX, pos_fmt="f"):
    """A minimal valid glTF (buffer as a data URI) like model/test/test_util.cc's minimal_gltf."""
    pos = struct.pack("<%d%s" % (len(positions), pos_fmt), *positions)
    idx = struct.pack("<%dI" % len(indices), *indices)
    data = pos + idx
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "quad"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4,
                                    "material": 0}]}],
        "materials": [{"name": "m", "pbrMetallicRoughness": {"metallicFactor": 0.0}}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(positions) // 3,
                       "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5125, "count": len(indices),
                       "type": "SCALAR"}],
    }


def glb(j):
    js = json.dumps(j).encode()
    js += b" " * (-len(js) % 4)
    return b"glTF" + struct.pack("<II", 2, 12 + 8 + len(js)) + struct.pack("<I", len(js)) + \
        b"JSON" + js


def edit(fn):
    """A glTF text made from the minimal one by fn(j) (which edits j in place)."""
    j = gltf()
    fn(j)
    return json.dumps(j)


def put(j, path, value):
    """Sets j[path...] = value where path is a list of keys / indices."""
    for k in path[:-1]:
        j = j[k]
    j[path[-1]] = value


OK_FINGERPRINT = [0]  # the valid scene's, read from the stream `hrpp trace` writes of it


def stream(records=3, fingerprint=None, options=b'{"generator":"tool_errors.py"}', version=1,
           header_len=None, count=None, patch=None, tail=b""):
    """A ray stream (docs/ray_stream.md); patch(record_index, bytearray) may corrupt records."""
    hl = header_len if header_len is not None else (36 + len(options) + 63) // 64 * 64
    h = bytearray(b"HRPPRAYS" + struct.pack("<IIQQI", version, hl,
                                            OK_FINGERPRINT[0] if fingerprint is None else fingerprint,
                                            records if count is None else count, len(options)))
    h += options
    h += b"\0" * max(0, hl - len(h))
    body = bytearray()
    for i in range(records):
        r = bytearray(struct.pack("<8f", 0.1 * i, 0.5, 3.0, 0.0, 0.0, -1.0, 0.0, 1e30))
        r += bytes([0, 0, 0, 0]) + struct.pack("<IIIQQ", i, 0, 0xFFFFFFFF, i, 2**64 - 1)
        if patch:
            patch(i, r)
        body += r
    return bytes(h) + bytes(body) + tail


def nan_record(i, r):
    if i == 1:
        r[16:20] = struct.pack("<I", 0x7FC00000)  # dir.y = NaN


def kind_record(i, r):
    if i == 2:
        r[32] = 6


def reserved_record(i, r):
    if i == 0:
        r[35] = 1


def inf_tnear(i, r):
    if i == 0:
        r[24:28] = struct.pack("<f", float("inf"))


# ---- the cases --------------------------------------------------------------------------------
# (name, files {name: bytes or str}, args (with {dir}, {scene} = a valid scene, {stream} = a
# valid stream of it), expected exit code, regex the error output must match)

OK_SCENE = ("ok.gltf", json.dumps(gltf()))

SCENE_CASES = [
    ("scene: no such file", {}, "info {dir}/missing.glb", "no such file"),
    ("scene: a directory", {}, "info {dir}", "is a directory, not a scene file"),
    ("scene: empty .glb", {"s.glb": b""}, "info {dir}/s.glb", r"not a binary glTF file \(bad magic\)"),
    ("scene: empty .gltf", {"s.gltf": b""}, "info {dir}/s.gltf", "invalid glTF"),
    ("scene: text in a .glb", {"s.glb": "hello"}, "info {dir}/s.glb", "bad magic"),
    ("scene: not JSON", {"s.gltf": "{ this is not json"}, "info {dir}/s.gltf", "invalid glTF"),
    ("scene: JSON array", {"s.gltf": "[1, 2]"}, "info {dir}/s.gltf", "invalid glTF"),
    ("scene: truncated .glb", {"s.glb": glb(gltf())[:40]}, "info {dir}/s.glb", "invalid glTF"),
    ("scene: .glb length field too large",
     {"s.glb": glb(gltf())[:8] + struct.pack("<I", 10**6) + glb(gltf())[12:]},
     "info {dir}/s.glb", "invalid glTF"),
    ("scene: .glb version 1", {"s.glb": b"glTF" + struct.pack("<I", 1) + glb(gltf())[8:]},
     "info {dir}/s.glb", "binary glTF version 1 is not supported"),
    ("scene: default scene out of range", {"s.gltf": edit(lambda j: put(j, ["scene"], 3))},
     "info {dir}/s.gltf", "scene"),
    ("scene: no triangles", {"s.gltf": edit(lambda j: put(j, ["scenes"], [{"nodes": []}]))},
     "info {dir}/s.gltf", "the default scene has no triangles"),
    ("scene: material index out of range",
     {"s.gltf": edit(lambda j: put(j, ["meshes", 0, "primitives", 0, "material"], 7))},
     "info {dir}/s.gltf", "material"),
    ("scene: material extension not a number",
     {"s.gltf": edit(lambda j: put(j, ["materials", 0, "extensions"],
                                   {"KHR_materials_ior": {"ior": "glass"}}))},
     "info {dir}/s.gltf", r"KHR_materials_ior\.ior is not a number"),
    ("scene: material factor overflows to infinity",
     {"s.gltf": edit(lambda j: put(j, ["materials", 0, "extensions"],
                                   {"KHR_materials_emissive_strength": {"emissiveStrength": 1e300}}))},
     "info {dir}/s.gltf", "NaN or infinite factor"),
    ("scene: node index out of range", {"s.gltf": edit(lambda j: put(j, ["scenes", 0, "nodes"], [5]))},
     "info {dir}/s.gltf", "node"),
    ("scene: node cycle",
     {"s.gltf": edit(lambda j: put(j, ["nodes"], [{"mesh": 0, "children": [1]}, {"children": [0]}]))},
     "info {dir}/s.gltf", r"node|cycle"),
    ("scene: shared children (2^30 paths: a hang before the check)",
     {"s.gltf": edit(lambda j: put(j, ["nodes"], [{"children": [2 * (k // 2) + 2, 2 * (k // 2) + 3]}
                                                  if k < 60 else {"mesh": 0} for k in range(62)]))},
     "info {dir}/s.gltf", r"node \d+ is reached more than once \(glTF node hierarchies must be trees\)"),
    ("scene: hierarchy 300 levels deep",
     {"s.gltf": edit(lambda j: put(j, ["nodes"], [{"children": [k + 1]} for k in range(300)] + [{"mesh": 0}]))},
     "info {dir}/s.gltf", r"deeper than 256 levels"),
    ("scene: matrix of 15 numbers",
     {"s.gltf": edit(lambda j: put(j, ["nodes", 0, "matrix"], [1] * 15))},
     "info {dir}/s.gltf", r"matrix"),
    ("scene: transform not finite",
     {"s.gltf": edit(lambda j: put(j, ["nodes", 0, "scale"], [1e300, 1e300, 1e300]))},
     "info {dir}/s.gltf", r"not finite|NaN or infinite"),
    ("scene: camera index out of range",
     {"s.gltf": edit(lambda j: j["nodes"].append({"camera": 4}) or put(j, ["scenes", 0, "nodes"], [0, 1]))},
     "info {dir}/s.gltf", "camera"),
    ("scene: camera yfov 0",
     {"s.gltf": edit(lambda j: (j["nodes"].append({"camera": 0}), put(j, ["scenes", 0, "nodes"], [0, 1]),
                                put(j, ["cameras"], [{"type": "perspective",
                                                      "perspective": {"yfov": 0, "znear": 0.1}}])))},
     "info {dir}/s.gltf", r"yfov"),
    ("scene: light without an index",
     {"s.gltf": edit(lambda j: (j["nodes"].append({"extensions": {"KHR_lights_punctual": {}}}),
                                put(j, ["scenes", 0, "nodes"], [0, 1])))},
     "info {dir}/s.gltf", "KHR_lights_punctual without a light index"),
    ("scene: light index out of range",
     {"s.gltf": edit(lambda j: (j["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": 3}}}),
                                put(j, ["scenes", 0, "nodes"], [0, 1])))},
     "info {dir}/s.gltf", "light index 3"),
    ("scene: light of unknown type",
     {"s.gltf": edit(lambda j: put(j, ["extensions"], {"KHR_lights_punctual": {"lights": [{"type": "laser"}]}}))},
     "info {dir}/s.gltf", r"unknown type 'laser'"),
    ("scene: light with zero scale",
     {"s.gltf": edit(lambda j: (j["nodes"].append({"scale": [0, 0, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}),
                                put(j, ["scenes", 0, "nodes"], [0, 1]),
                                put(j, ["extensions"], {"KHR_lights_punctual": {"lights": [{"type": "point"}]}})))},
     "info {dir}/s.gltf", "zero scale"),
    ("scene: sparse accessor",
     {"s.gltf": edit(lambda j: put(j, ["accessors", 0, "sparse"],
                                   {"count": 1, "indices": {"bufferView": 1, "componentType": 5125},
                                    "values": {"bufferView": 0}}))},
     "info {dir}/s.gltf", r"sparse"),
    ("scene: bufferView index out of range", {"s.gltf": edit(lambda j: put(j, ["accessors", 0, "bufferView"], 9))},
     "info {dir}/s.gltf", "bufferView"),
    ("scene: buffer index out of range", {"s.gltf": edit(lambda j: put(j, ["bufferViews", 0, "buffer"], 4))},
     "info {dir}/s.gltf", "buffer"),
    ("scene: byteStride smaller than a vertex",
     {"s.gltf": edit(lambda j: put(j, ["bufferViews", 0, "byteStride"], 4))},
     "info {dir}/s.gltf", r"byteStride"),
    ("scene: accessor beyond its bufferView", {"s.gltf": edit(lambda j: put(j, ["accessors", 0, "count"], 400))},
     "info {dir}/s.gltf", r"bufferView|exceed|beyond|out of"),
    ("scene: POSITION accessor out of range",
     {"s.gltf": edit(lambda j: put(j, ["meshes", 0, "primitives", 0, "attributes", "POSITION"], 9))},
     "info {dir}/s.gltf", "POSITION accessor"),
    ("scene: POSITION not VEC3 float", {"s.gltf": edit(lambda j: put(j, ["accessors", 0, "type"], "VEC2"))},
     "info {dir}/s.gltf", "POSITION accessor 0"),
    ("scene: NaN vertex", {"s.gltf": json.dumps(gltf(positions=QUAD[:4] + [float("nan")] + QUAD[5:]))},
     "info {dir}/s.gltf", r"NaN or infinite"),
    ("scene: infinite vertex", {"s.gltf": json.dumps(gltf(positions=[float("inf")] + QUAD[1:]))},
     "info {dir}/s.gltf", r"NaN or infinite"),
    ("scene: coordinates of -3e38 and 3e38 (the extent overflows float32)",
     {"s.gltf": json.dumps(gltf(positions=[-3e38, 0, 0, 3e38, 0, 0, 3e38, 1, 0, 0, 1, 0]))},
     "info {dir}/s.gltf", r"node 0 \(quad\) mesh 0 primitive 0: vertex 0 has the world coordinate -3\.00000001e\+38, "
                          r"outside the traceable range \|x\| <= 1\.37438953e\+11"),
    ("scene: indices accessor out of range",
     {"s.gltf": edit(lambda j: put(j, ["meshes", 0, "primitives", 0, "indices"], 8))},
     "info {dir}/s.gltf", "indices accessor"),
    ("scene: float indices", {"s.gltf": edit(lambda j: put(j, ["accessors", 1, "componentType"], 5126))},
     "info {dir}/s.gltf", r"indices accessor|componentType"),
    ("scene: vertex index out of range", {"s.gltf": json.dumps(gltf(indices=[0, 1, 2, 0, 2, 99]))},
     "info {dir}/s.gltf", r"index 99 at position 5"),
    ("scene: mesh index out of range", {"s.gltf": edit(lambda j: put(j, ["nodes", 0, "mesh"], 2))},
     "info {dir}/s.gltf", r"mesh"),
    ("scene: POINTS primitive", {"s.gltf": edit(lambda j: put(j, ["meshes", 0, "primitives", 0, "mode"], 0))},
     "info {dir}/s.gltf", r"POINTS"),
    ("scene: no POSITION attribute",
     {"s.gltf": edit(lambda j: put(j, ["meshes", 0, "primitives", 0, "attributes"], {"NORMAL": 0}))},
     "info {dir}/s.gltf", "no POSITION attribute"),
    ("scene: TRIANGLES with 4 indices",
     {"s.gltf": edit(lambda j: put(j, ["accessors", 1, "count"], 4))},
     "info {dir}/s.gltf", "TRIANGLES with 4"),
    ("scene: external buffer missing",
     {"s.gltf": edit(lambda j: put(j, ["buffers", 0, "uri"], "missing.bin"))},
     "info {dir}/s.gltf", r"missing\.bin"),
    ("scene: external buffer is a device",
     {"s.gltf": edit(lambda j: put(j, ["buffers", 0, "uri"], "/dev/zero"))},
     "info {dir}/s.gltf", r"/dev/zero' is not a regular file|not found : /dev/zero"),
    ("scene: external buffer is a FIFO (blocked forever before the check)",
     {"s.gltf": edit(lambda j: put(j, ["buffers", 0, "uri"], "fifo.bin")), "fifo.bin": None},
     "info {dir}/s.gltf", r"fifo\.bin' is not a regular file"),
]

SIDECAR_CASES = [
    ("sidecar: bad JSON", {"c.camera.json": "{ nope"}, "info {dir}/c.gltf", r"c\.camera\.json: bad JSON"),
    ("sidecar: not an object", {"c.camera.json": "[1]"}, "info {dir}/c.gltf", "must hold a JSON object"),
    ("sidecar: missing eye", {"c.camera.json": json.dumps({"target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40})},
     "info {dir}/c.gltf", "missing key 'eye'"),
    ("sidecar: eye of 2 numbers", {"c.camera.json": json.dumps({"eye": [0, 0], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40})},
     "info {dir}/c.gltf", "'eye' must be 3 numbers"),
    ("sidecar: eye is target", {"c.camera.json": json.dumps({"eye": [1, 1, 1], "target": [1, 1, 1], "up": [0, 1, 0], "fov_y_deg": 40})},
     "info {dir}/c.gltf", "eye and target coincide"),
    ("sidecar: up parallel", {"c.camera.json": json.dumps({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, 1], "fov_y_deg": 40})},
     "info {dir}/c.gltf", "'up' is zero or parallel"),
    ("sidecar: fov 180", {"c.camera.json": json.dumps({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 180})},
     "info {dir}/c.gltf", r"'fov_y_deg' must be in \(0, 180\)"),
    ("sidecar: negative aspect", {"c.camera.json": json.dumps({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40, "aspect": -1})},
     "info {dir}/c.gltf", "'aspect' must be a positive number"),
    ("sidecar: bad image size", {"c.camera.json": json.dumps({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40, "image_size": [0, 5]})},
     "info {dir}/c.gltf", "'image_size' must be two positive integers"),
]
for _, files, _, _ in SIDECAR_CASES:
    files["c.gltf"] = json.dumps(gltf())

STREAM_CASES = [
    ("stream: missing", {}, "predict {scene} --stream {dir}/none.rays", "cannot open"),
    ("stream: a directory", {}, "predict {scene} --stream {dir}", "not a regular file"),
    ("stream: empty", {"s.rays": lambda: b""}, "predict {scene} --stream {dir}/s.rays", r"truncated header|bad magic"),
    ("stream: bad magic", {"s.rays": lambda: b"HRPPRAYZ" + stream()[8:]}, "predict {scene} --stream {dir}/s.rays", r"not a ray stream \(bad magic\)"),
    ("stream: truncated header", {"s.rays": lambda: stream()[:20]}, "predict {scene} --stream {dir}/s.rays", "truncated header"),
    ("stream: version 2", {"s.rays": lambda: stream(version=2)}, "predict {scene} --stream {dir}/s.rays", "ray-stream version 2 is not supported"),
    ("stream: header length not a multiple of 64", {"s.rays": lambda: stream(header_len=100)}, "predict {scene} --stream {dir}/s.rays", "bad header length 100"),
    ("stream: header length beyond the file", {"s.rays": lambda: stream(records=0, header_len=6400)[:128]}, "predict {scene} --stream {dir}/s.rays", "truncated header"),
    ("stream: truncated records", {"s.rays": lambda: stream(count=5)}, "predict {scene} --stream {dir}/s.rays", r"truncated at record 3 \(expected 5 records\)"),
    ("stream: trailing bytes", {"s.rays": lambda: stream(tail=b"x" * 10)}, "predict {scene} --stream {dir}/s.rays", "10 bytes after the 3 records"),
    ("stream: NaN direction", {"s.rays": lambda: stream(patch=nan_record)}, "predict {scene} --stream {dir}/s.rays", r"record 1: NaN or infinite field \(dir\.y\)"),
    ("stream: infinite tnear", {"s.rays": lambda: stream(patch=inf_tnear)}, "predict {scene} --stream {dir}/s.rays", r"record 0: NaN or infinite field \(tnear\)"),
    ("stream: unknown kind", {"s.rays": lambda: stream(patch=kind_record)}, "predict {scene} --stream {dir}/s.rays", "record 2: unknown ray kind 6"),
    ("stream: reserved bytes", {"s.rays": lambda: stream(patch=reserved_record)}, "predict {scene} --stream {dir}/s.rays", "reserved bytes 34-35 are not zero"),
    ("stream: another scene's", {"s.rays": lambda: stream(fingerprint=1234)}, "predict {scene} --stream {dir}/s.rays", "was generated from another scene"),
]

P = "predict {scene} --res 4x4 "
OPTION_CASES = [
    ("option: no subcommand", {}, "", "subcommand"),
    ("option: unknown subcommand", {}, "frobnicate", r"frobnicate|subcommand"),
    ("option: table with 0 sets", {}, P + "--table 0x4", r"--table must be 'unbounded' or SETSxWAYS"),
    ("option: table with 0 ways", {}, P + "--table 64x0", r"--table must be"),
    ("option: sets not a power of two", {}, P + "--table 96x4", "the number of sets must be a power of two"),
    ("option: 17 ways", {}, P + "--table 64x17", "ways must be 1..16, got 17"),
    ("option: 2^25 sets", {}, P + "--table 33554432x1", r"--table must be 'unbounded' or SETSxWAYS"),
    ("option: table not WxH", {}, P + "--table big", r"--table must be"),
    ("option: precision larger than the mantissa", {}, P + "--precision 24", r"--precision.*24"),
    ("option: precision 0", {}, P + "--precision 0", r"--precision"),
    ("option: exponent bits 9", {}, P + "--exp-bits 9", r"--exp-bits"),
    ("option: key over 64 bits", {}, P + "--precision 10 --exp-bits 8 --combine concat --table unbounded",
     "at most 64 are supported"),
    ("option: more sets than key bits", {}, P + "--precision 1 --exp-bits 0 --table 1024x2",
     r"keys have only 6 bits"),
    ("option: origin bits 17", {}, P + "--hash improved --origin-bits 17", r"--origin-bits"),
    ("option: direction bits 0", {}, P + "--hash improved --dir-bits 0", r"--dir-bits"),
    ("option: tag bits 65", {}, P + "--table 64x4 --tag-bits 65", r"--tag-bits"),
    ("option: tag bits over the tag", {}, P + "--table 64x4 --tag-bits 60", r"--tag-bits 60 exceeds the full tag width"),
    ("option: nodes per entry 0", {}, P + "--nodes-per-entry 0", r"--nodes-per-entry"),
    ("option: go-up 65", {}, P + "--go-up 65", r"--go-up"),
    ("option: unknown hash", {}, P + "--hash perfect", r"--hash"),
    ("option: unknown mode", {}, P + "--mode fastest", r"--mode"),
    ("option: unknown combine", {}, P + "--combine add", r"--combine"),
    ("option: not a number", {}, P + "--precision six", r"--precision"),
    ("option: spp 0", {}, P + "--spp 0", r"--spp"),
    ("option: res 0x0", {}, "predict {scene} --res 0x0", r"--res must be WIDTHxHEIGHT"),
    ("option: res negative", {}, "predict {scene} --res -4x4", r"--res"),
    ("option: depth 17", {}, P + "--depth 17", r"--depth"),
    ("option: tile 0", {}, P + "--tile 0 --order tiled", r"--tile"),
    ("option: unknown order", {}, P + "--order spiral", r"--order"),
    ("option: unknown workload", {}, "predict {scene} --workload sobol", r"--workload"),
    ("option: unknown bvh", {}, P + "--bvh sbvh", r"--bvh: sbvh not in \{sah,micro21-sbvh\}"),
    ("option: simulate unknown bvh", {}, "simulate {scene} --res 4x4 --bvh embree", r"--bvh"),
    ("option: trace unknown bvh", {}, "trace {scene} --res 4x4 --out {dir}/x.rays --bvh SAH", r"--bvh"),
    ("option: check-embree unknown bvh", {}, "check-embree {scene} --bvh micro21", r"--bvh"),
    ("option: info unknown bvh", {}, "info {scene} --bvh none", r"--bvh"),
    ("option: micro21-ao with a resolution", {}, P + "--workload micro21-ao",
     r"--workload micro21-ao has no camera and its own AO rays \(one per triangle, unbounded\): "
     r"--res, --spp, --order and --ao-distance do not apply"),
    ("option: micro21-ao-sorted with a resolution", {}, P + "--workload micro21-ao-sorted",
     r"--workload micro21-ao-sorted has no camera"),
    ("option: flipped AO normal on the camera workload", {},
     "predict {scene} --ao-normal flipped", r"--ao-normal applies to MICRO 2021's AO workloads"),
    ("option: unknown AO normal", {}, "predict {scene} --workload micro21-ao --ao-normal up",
     r"--ao-normal"),
    ("option: simulate warm-up of every ray", {},
     "simulate {scene} --workload micro21-ao --preset micro21 --warmup-rays 100",
     r"--warmup-rays 100 leaves no rays to measure \(\d+ rays\)"),
    ("option: simulate unknown mesh", {}, "simulate {scene} --res 4x4 --meshes teapot",
     r"--meshes: no mesh 'teapot' in .* \(its meshes: "),
    ("option: simulate replay on the RTL's cycle model", {},
     "simulate {scene} --res 4x4 --preset rtl-default --replay",
     r"--replay settles the golden predictor's fetch lists; rtl-default runs the RTL's cycle "
     r"model"),
    ("option: simulate unknown repacking", {}, "simulate {scene} --res 4x4 --repack --repack-by "
     "lane", r"--repack-by"),
    ("option: simulate --repack-by without --repack", {},
     "simulate {scene} --res 4x4 --repack-by micro21", r"--repack-by chooses how --repack "
     r"regroups rays; add --repack"),
    ("option: simulate unknown cycle count", {}, "simulate {scene} --res 4x4 --cycles-until "
     "warps", r"--cycles-until"),
    ("option: negative AO distance", {}, P + "--ao-distance -1", r"--ao-distance"),
    ("option: NaN AO distance", {}, P + "--ao-distance nan", r"--ao-distance"),
    ("option: -inf AO distance", {}, P + "--ao-distance -inf", r"--ao-distance: must be a number >= 0 or 'inf', got -inf"),
    ("option: unknown preset", {}, P + "--preset micro22", r"--preset"),
    ("option: micro21 theta bits 9", {}, P + "--hash micro21 --dir-bits 9", r"theta bits \(--dir-bits\) must be 1\.\.8"),
    ("option: octahedral direction bits 9", {}, P + "--hash improved --dir-code oct --dir-bits 9",
     r"octahedral direction bits \(--dir-bits with --dir-code oct\) must be 1\.\.8, got 9"),
    ("option: unknown direction code", {}, P + "--hash improved --dir-code cube", r"--dir-code"),
    ("option: unknown predict kinds", {}, P + "--predict-kinds shadow", r"--predict-kinds"),
    ("option: unknown effect", {}, P + "--effects shadow,glitter", r"unknown effect 'glitter'"),
    ("option: stream with workload options", {}, "predict {scene} --stream {stream} --spp 2", r"excludes"),
    ("option: check-embree 0 rays", {}, "check-embree {scene} --rays 0", r"--rays"),
    ("option: check-embree unknown kind", {}, "check-embree {scene} --kind laser", r"--kind"),
    ("option: leaf size 0", {}, "info {scene} --leaf-size 0", r"--leaf-size"),
    ("option: leaf size 65", {}, "info {scene} --leaf-size 65", r"--leaf-size"),
    ("option: trace without --out", {}, "trace {scene} --res 4x4", r"--out is required"),
    ("option: trace into a missing directory", {}, "trace {scene} --res 4x4 --out {dir}/no/x.rays",
     r"hrpp trace: --out \S*/no/x\.rays: the folder '\S*/no' does not exist"),
    ("option: render --out is a file", {}, "render {scene} --res 4x4 --out {scene}",
     r"hrpp render: --out \S*ok\.gltf: '\S*ok\.gltf' is a file, not a folder"),
]

# Outputs checked before the work starts (issue 20): the scene is missing, so an output checked
# only after loading it (or, before, only when written at the end) shows "no such file" instead.
M = "{dir}/missing.glb"
OUTPUT_CASES = [
    ("output: predict --json in a missing folder", {}, "predict " + M + " --json {dir}/no/r.json",
     r"^hrpp predict: --json \S*/no/r\.json: the folder '\S*/no' does not exist\n$"),
    ("output: predict --json names a folder", {}, "predict " + M + " --json {dir}",
     r"hrpp predict: --json \S+: '\S+' is a folder, not a file"),
    ("output: predict --json under a file", {"f": "x"}, "predict " + M + " --json {dir}/f/r.json",
     r"hrpp predict: --json \S*/f/r\.json: '\S*/f' is not a folder"),
    ("output: predict --spec-images is a file", {"f": "x"}, "predict " + M + " --spec-images {dir}/f",
     r"hrpp predict: --spec-images \S*/f: '\S*/f' is a file, not a folder"),
    ("output: predict --spec-images under a file", {"f": "x"},
     "predict " + M + " --spec-images {dir}/f/a/b", r"hrpp predict: --spec-images \S*/f/a/b: '\S*/f' is not a folder"),
    ("output: simulate --json in a missing folder", {}, "simulate " + M + " --json {dir}/no/s.json",
     r"hrpp simulate: --json \S*/no/s\.json: the folder '\S*/no' does not exist"),
    ("output: check-embree --json names a folder", {}, "check-embree " + M + " --json {dir}",
     r"hrpp check-embree: --json \S+: '\S+' is a folder, not a file"),
    ("output: info --json in a missing folder", {}, "info " + M + " --json {dir}/no/i.json",
     r"hrpp info: --json \S*/no/i\.json: the folder '\S*/no' does not exist"),
    ("output: trace --out names a folder", {}, "trace " + M + " --out {dir}",
     r"hrpp trace: --out \S+: '\S+' is a folder, not a file"),
    ("output: trace --out - (a ray stream is a file)", {}, "trace " + M + " --out -",
     r"hrpp trace: --out -: standard output is not supported for this option"),
    ("output: trace --json in a missing folder", {}, "trace " + M + " --out {dir}/t.rays --json {dir}/no/t.json",
     r"hrpp trace: --json \S*/no/t\.json: the folder '\S*/no' does not exist"),
    ("output: render --out a folder that is not a render's", {"mine.txt": "x"},
     "render " + M + " --out {dir}",
     r"hrpp render: --out \S+: the folder holds files that are not an earlier render's"),
    ("output: render --out under a file", {"f": "x"}, "render " + M + " --out {dir}/f/pics",
     r"hrpp render: --out \S*/f/pics: '\S*/f' is not a folder"),
    ("output: sweep --csv names a folder", {}, "sweep " + M + " --param precision=5 --csv {dir}",
     r"hrpp sweep: --csv \S+: '\S+' is a folder, not a file"),
    ("output: sweep --csv under a file", {"f": "x"}, "sweep " + M + " --param precision=5 --csv {dir}/f/s.csv",
     r"hrpp sweep: --csv \S*/f/s\.csv: '\S*/f' is not a folder"),
    ("output: sweep --plots is a file", {"f": "x"},
     "sweep " + M + " --param precision=5 --csv {dir}/s.csv --plots {dir}/f",
     r"hrpp sweep: --plots \S*/f: '\S*/f' is a file, not a folder"),
    ("output: sweep --report names a folder", {}, "sweep --from-csv {dir}/none.csv --report {dir}",
     r"hrpp sweep: --report \S+: '\S+' is a folder, not a file"),
]


# Options that the configuration does not use are refused, naming what they go with (issue 20);
# only options given count, never a preset's values.
APPLIES = r"applies only to "
INAPPLICABLE_CASES = [
    ("inapplicable: --precision with --hash improved", {}, P + "--hash improved --precision 5",
     r"hrpp predict: --precision " + APPLIES + r"the faithful hash \(--hash faithful\); this run "
     r"uses --hash improved"),
    ("inapplicable: --exp-bits with --hash micro21", {}, P + "--hash micro21 --exp-bits 2",
     r"--exp-bits " + APPLIES + r"the faithful hash.*this run uses --hash micro21"),
    ("inapplicable: --precision with --preset micro21", {}, P + "--preset micro21 --precision 6",
     r"--precision " + APPLIES + r"the faithful hash.*this run uses --preset micro21 \(hash micro21\)"),
    ("inapplicable: --origin-bits with the default (faithful) hash", {}, P + "--origin-bits 4",
     r"--origin-bits " + APPLIES + r"the improved and micro21 hashes \(--hash improved\|micro21\); "
     r"this run uses the default hash faithful"),
    ("inapplicable: --dir-bits with --hash faithful", {}, P + "--hash faithful --dir-bits 2",
     r"--dir-bits " + APPLIES + r"the improved and micro21 hashes.*this run uses --hash faithful"),
    ("inapplicable: --dir-code with --preset micro21", {}, P + "--preset micro21 --dir-code oct",
     r"--dir-code " + APPLIES + r"the improved hash \(--hash improved\); this run uses --preset "
     r"micro21 \(hash micro21\)"),
    ("inapplicable: --dir-code with the default (faithful) hash", {}, P + "--dir-code oct",
     r"--dir-code " + APPLIES + r"the improved hash.*this run uses the default hash faithful"),
    ("inapplicable: --tag-bits with --table unbounded", {}, P + "--table unbounded --tag-bits 8",
     r"--tag-bits " + APPLIES + r"a set-associative table \(--table SETSxWAYS\); this run uses "
     r"--table unbounded"),
    ("inapplicable: --tag-bits with --preset study2019", {}, P + "--preset study2019 --tag-bits 8",
     r"--tag-bits " + APPLIES + r"a set-associative table.*--preset study2019 \(table unbounded\)"),
    ("inapplicable: render --precision with --hash improved", {},
     "render {scene} --res 4x4 --out {dir}/r --hash improved --precision 5", r"hrpp render: --precision " + APPLIES),
    ("inapplicable: simulate --origin-bits with --hash faithful", {},
     "simulate {scene} --res 4x4 --hash faithful --origin-bits 5", r"hrpp simulate: --origin-bits " + APPLIES),
    ("inapplicable: info --leaf-size with --bvh micro21-sbvh", {},
     "info {scene} --bvh micro21-sbvh --leaf-size 8",
     r"hrpp info: --leaf-size " + APPLIES + r"our SAH build \(--bvh sah\); this run uses --bvh "
     r"micro21-sbvh"),
]


def square(h, z):
    """The minimal scene's quad scaled to half-size h in the plane z."""
    return json.dumps(gltf(positions=[-h, -h, z, h, -h, z, h, h, z, -h, h, z]))


def with_light(position):
    j = gltf()
    j["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "name": "far"}]}}
    j["extensionsUsed"] = ["KHR_lights_punctual"]
    j["nodes"].append({"translation": position, "extensions": {"KHR_lights_punctual": {"light": 0}}})
    j["scenes"][0]["nodes"].append(1)
    return json.dumps(j)


RANGE = r"outside the traceable range \|x\| <= "
# The valid range (docs/bvh.md, "Valid range") and the cross-check's verdicts: (name, files,
# arguments, exit code, stderr regex). Before the range was enforced, `info` printed "SAH cost -nan"
# for 1e19, check-embree aborted inside Embree (exit 134) for 1e18, and printed PASS with nothing
# compared.
RANGE_CASES = [
    ("inapplicable: a preset's own values never count (rtl-primary: improved hash, tag bits)", {},
     P + "--preset rtl-primary", 0, r"^$"),
    ("inapplicable: --origin-bits with --preset rtl-primary (improved hash) applies", {},
     P + "--preset rtl-primary --origin-bits 4", 0, r"^$"),
    ("range: coordinates of 1e19 (info printed SAH cost -nan)", {"s.gltf": square(1e19, 0)},
     "info {dir}/s.gltf", 2, r"node 0 \(quad\) mesh 0 primitive 0: vertex 0 has the world coordinate "
                             r"-9\.99999998e\+18, " + RANGE + r"1\.37438953e\+11"),
    ("range: coordinates of 1e18 (check-embree aborted on the default camera's rays)",
     {"s.gltf": square(1e18, 0)}, "check-embree {dir}/s.gltf --rays 100", 2,
     r"vertex 0 has the world coordinate -9\.99999984e\+17, " + RANGE),
    ("range: a square of half-size 1e12 at distance 1e14 (silently missed)",
     {"s.gltf": square(1e12, 1e14)}, "info {dir}/s.gltf", 2, r"world coordinate -9\.99999996e\+11, " + RANGE),
    ("range: a triangle of twice the area 1e-40 (silently missed)",
     {"s.gltf": json.dumps(gltf(positions=[0, 0, 0, 1e-20, 0, 0, 1e-20, 1e-20, 0, 0, 1e-20, 0]))},
     "info {dir}/s.gltf", 2, r"triangle 0 has twice the area 9\.99999\d+e-41, below the smallest traceable"),
    ("range: a camera eye at 2e12", {"c.gltf": json.dumps(gltf()), "c.camera.json":
     json.dumps({"eye": [0, 0, 2e12], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40})},
     "info {dir}/c.gltf", 2, r"camera \(sidecar c\.camera\.json\): the eye coordinate 1\.99999999e\+12 is " + RANGE),
    ("range: a point light at 3e12", {"s.gltf": with_light([3e12, 0, 0])}, "info {dir}/s.gltf", 2,
     r"node 1: light 'far' has the position coordinate 3\.00000005e\+12, " + RANGE),
    ("range: info at the range's corner (half-size 2^37) prints no NaN or infinity",
     {"s.gltf": square(2.0 ** 37, 2.0 ** 37)}, "info {dir}/s.gltf", 0, r"^$"),
    ("range: info on a scene of zero-area triangles prints no NaN or infinity",
     {"s.gltf": json.dumps(gltf(positions=[1, 1, 1] * 4))}, "info {dir}/s.gltf", 0, r"^$"),
    ("check-embree: no ray compared (shadow rays of a scene without lights) fails",
     {"s.gltf": json.dumps(gltf())}, "check-embree {dir}/s.gltf --kind shadow --rays 100", 1,
     r"hrpp check-embree: FAIL: no ray compared \(0 rays of the kinds asked for"),
    ("check-embree: a valid scene passes", {"s.gltf": square(1, -1)},
     "check-embree {dir}/s.gltf --rays 400", 0, r"^$"),
]

CASES = [(n, f, a, 2, r) for n, f, a, r in
         SCENE_CASES + SIDECAR_CASES + STREAM_CASES + OPTION_CASES + OUTPUT_CASES +
         INAPPLICABLE_CASES]
CASES += RANGE_CASES
MALFORMED_FILES = len(SCENE_CASES) + len(SIDECAR_CASES) + len(STREAM_CASES)

NAN_RE = re.compile(r"(?<![A-Za-z_])(-?nan|-?inf)(?![A-Za-z_])", re.IGNORECASE)


def run_case(tool, base, i, case):
    name, files, args, code, regex = case
    d = os.path.join(base, "case%03d" % i)
    os.makedirs(d)
    for fname, content in files.items():
        if content is None:
            os.mkfifo(os.path.join(d, fname))
            continue
        with open(os.path.join(d, fname), "wb") as f:
            f.write(content() if callable(content) else
                    content.encode() if isinstance(content, str) else content)
    argv = [tool] + [a.format(dir=d, scene=os.path.join(base, OK_SCENE[0]),
                              stream=os.path.join(base, "ok.rays")) for a in args.split()]
    try:
        p = subprocess.run(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, errors="replace", timeout=60)
    except subprocess.TimeoutExpired:
        return "hangs (no exit within 60 s)"
    problems = []
    if p.returncode != code:
        problems.append("exit code %d, expected %d" % (p.returncode, code))
    if not re.search(regex, p.stderr):
        problems.append("stderr does not match /%s/" % regex)
    # Figures with NaN / inf, anywhere except where the tool echoes the bad input back.
    for line in (p.stdout + p.stderr).splitlines():
        if NAN_RE.search(line) and not any(w in line for w in ("--ao-distance", "NaN or infinite")):
            problems.append("NaN/inf in output: " + line.strip())
    if problems:
        return "; ".join(problems) + "\n    $ " + " ".join(argv) + "\n    stdout: " + \
            p.stdout.strip()[-500:] + "\n    stderr: " + p.stderr.strip()[-500:]
    return None


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    tool = sys.argv[1]
    if "--list" in sys.argv[2:]:
        for c in CASES:
            print(c[0])
        return 0
    if not os.access(tool, os.X_OK):
        print("tool_errors.py: %s is not an executable" % tool, file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="hrpp-tool-errors-") as base:
        with open(os.path.join(base, OK_SCENE[0]), "w") as f:
            f.write(OK_SCENE[1])
        # A valid stream of the valid scene, for the option cases that need one.
        p = subprocess.run([tool, "trace", os.path.join(base, OK_SCENE[0]), "--res", "4x4",
                            "--out", os.path.join(base, "ok.rays")], capture_output=True, text=True)
        if p.returncode != 0:
            print("tool_errors.py: the valid scene does not trace:\n" + p.stdout + p.stderr)
            return 1
        with open(os.path.join(base, "ok.rays"), "rb") as f:
            OK_FINGERPRINT[0] = struct.unpack("<Q", f.read(24)[16:24])[0]
        failed = 0
        for i, case in enumerate(CASES):
            err = run_case(tool, base, i, case)
            if err:
                failed += 1
                print("FAIL %s: %s" % (case[0], err))
        print("tool.errors: %d cases (%d malformed files: %d scenes, %d camera sidecars, "
              "%d ray streams; %d bad options; %d outputs; %d inapplicable options; %d valid-range "
              "and check verdicts), %d failed"
              % (len(CASES), MALFORMED_FILES, len(SCENE_CASES), len(SIDECAR_CASES),
                 len(STREAM_CASES), len(OPTION_CASES), len(OUTPUT_CASES),
                 len(INAPPLICABLE_CASES), len(RANGE_CASES), failed))
        return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
