# Blender headless check of an exported rig (run by tests/cli_gltf_blender.sh):
#   blender -b --python-exit-code 1 --python blender_check.py -- RIG.glb ICT_DIR
# Imports the .glb with Blender's own glTF importer, checks that every morph target of the
# file arrives as a shape key with its ARKit name, and that the mesh with jawOpen at 1.0
# matches ICT_DIR/jawOpen.obj (centimetres -> metres, glTF Y-up -> Blender Z-up) within
# 1e-5 m on every vertex. Prints the numbers; exits nonzero on failure.
import json
import struct
import sys
import warnings

import numpy

# Debian 12's Blender 3.4 importer still uses the numpy aliases numpy 1.24 removed.
warnings.simplefilter("ignore", FutureWarning)
for alias, value in (("bool", bool), ("int", int), ("float", float), ("object", object)):
    if not hasattr(numpy, alias):
        setattr(numpy, alias, value)

import bpy  # noqa: E402

TOLERANCE = 1e-5


def fail(message):
    print("BLENDER CHECK FAILED: " + message)
    sys.exit(1)


def target_names(glb_path):
    with open(glb_path, "rb") as f:
        data = f.read()
    length, kind = struct.unpack_from("<II", data, 12)
    if kind != 0x4E4F534A:
        fail("first chunk is not JSON")
    doc = json.loads(data[20:20 + length])
    return doc["meshes"][0]["extras"]["targetNames"]


def read_obj_vertices(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                rows.append([float(t) for t in line.split()[1:4]])
    return numpy.array(rows, dtype=numpy.float64)


def to_blender(cm):
    """ICT centimetres, Y-up -> metres (as float32, like the file), Blender Z-up."""
    m = (cm / 100.0).astype(numpy.float32).astype(numpy.float64)
    return numpy.stack([m[:, 0], -m[:, 2], m[:, 1]], axis=1)


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    glb, ict = args[0], args[1]
    names = target_names(glb)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=glb)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if len(meshes) != 1:
        fail("expected one mesh object, found %d" % len(meshes))
    obj = meshes[0]
    keys = obj.data.shape_keys.key_blocks
    key_names = [k.name for k in keys][1:]
    missing = [n for n in names if n not in key_names]
    print("shape keys: %d (file targets: %d), missing: %s" % (len(key_names), len(names), missing or "none"))
    if missing or len(key_names) != len(names):
        fail("shape keys do not match the file's targets")

    world = numpy.array(obj.matrix_world)
    nv = len(obj.data.vertices)

    def coords(block):
        co = numpy.zeros(nv * 3)
        block.data.foreach_get("co", co)
        co = co.reshape(-1, 3)
        return co @ world[:3, :3].T + world[:3, 3]

    basis = coords(keys[0])
    jaw = coords(keys["jawOpen"])  # the mesh with jawOpen at 1.0 and every other key at 0

    neutral = to_blender(read_obj_vertices(ict + "/generic_neutral_mesh.obj"))
    expected = to_blender(read_obj_vertices(ict + "/jawOpen.obj"))
    # Match each Blender vertex to the ICT vertices at its neutral position (UV seams and
    # material borders split ICT vertices; a few ICT vertices coincide).
    groups = {}
    for i, p in enumerate(numpy.round(neutral, 7)):
        groups.setdefault(tuple(p), []).append(i)
    covered = numpy.zeros(len(neutral), dtype=bool)
    worst = 0.0
    unmatched = 0
    for b in range(nv):
        cands = groups.get(tuple(numpy.round(basis[b], 7)))
        if cands is None:
            d = numpy.linalg.norm(neutral - basis[b], axis=1)
            j = int(numpy.argmin(d))
            if d[j] > 1e-6:
                unmatched += 1
                continue
            cands = [j]
        err = min(numpy.abs(expected[c] - jaw[b]).max() for c in cands)
        worst = max(worst, err)
        covered[cands] = True
    print("blender vertices: %d, ICT vertices: %d covered of %d, unmatched: %d" %
          (nv, int(covered.sum()), len(neutral), unmatched))
    print("jawOpen=1.0 vs jawOpen.obj: max abs error %.3g m (tolerance %g)" % (worst, TOLERANCE))
    if unmatched or not covered.all():
        fail("the imported mesh does not cover the ICT vertices")
    if not worst <= TOLERANCE:
        fail("jawOpen differs from the ICT shape")
    print("BLENDER CHECK OK")


main()
