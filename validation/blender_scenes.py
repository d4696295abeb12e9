#!/usr/bin/env python3
"""Build the validation scenes that come from Blender: each made in Blender (`bpy` from PyPI) and
written by Blender's own glTF exporter, as users' files are made, with its Mitsuba twin.

    pip install "bpy==4.5.*" numpy
    python validation/blender_scenes.py            # every scene below
    python validation/blender_scenes.py NAME ...   # some
    python validation/make_references.py NAME ...  # their Mitsuba references (pip install mitsuba)

For every scene NAME this writes, into validation/NAME/:
- NAME.glb: the scene as Blender's glTF exporter writes it (default options, +Y up, a camera),
  with the objects' materials, normals (smooth or flat as shaded in Blender), UVs and textures;
- NAME.toml: Photon's scene: the camera, box filter, 128 x 128, and one `type = "mesh"` shape
  reading NAME.glb with the file's own materials and emission;
- NAME.xml: Mitsuba 3's scene, reading the same geometry from PLY files (below);
- OBJECT-MATERIAL.ply: for Mitsuba, every object split by material, taken from the same Blender
  meshes the exporter reads (the evaluated mesh's loop triangles, their corner normals and UVs,
  world space turned +Y up as the glTF exporter turns it: Blender (x, y, z) -> (x, z, -y));
  binary little-endian float32 x y z nx ny nz u v, v up as in Blender (and Photon);
- the PNG textures (also embedded in the glb) and their copies split for Mitsuba (colour and
  opacity of the alpha-masked card).

The script checks after each export that the glb carries what it should (the extensions, alpha
mode, double-sidedness) and that every PLY triangle corner matches the glb's vertices (position,
normal, uv; the glb's uv turned back to v up).

Materials: Blender's Principled BSDF. Its "Specular IOR Level" is set to 0 on the diffuse
surfaces, which the exporter writes as KHR_materials_specular specularFactor 0: a glTF
metallic-roughness material whose specular coat is off is Lambertian (base colour / pi), which
is Mitsuba's `diffuse` (wrapped in `twosided`: Blender's surfaces are double-sided). Emissive
meshes have Emission Color/Strength on the same Principled BSDF (emissiveFactor and
KHR_materials_emissive_strength) and a base colour: they reflect light too; the exporter marks
them doubleSided (Blender does not cull back faces), so they emit from both faces. Mitsuba's area
emitters are one-sided: a two-sided emitter is written as two copies 0.1 mm either side of the
surface, facing away from each other, each with the emitter and the reflecting BSDF.

Conventions (Photon <-> Mitsuba) are validation/README.md's; in particular Mitsuba's texture v = 0
is the image's top row, so bitmaps read the PLYs' v-up coordinates through to_uv (u, 1 - v).
"""

import json
import math
import os
import struct
import sys
import zlib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
RES = 128
EMITTER_GAP = 1e-4  # each Mitsuba copy of a two-sided emitter sits this far off the surface

WHITE = (0.7, 0.7, 0.7)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)


# --------------------------------------------------------------------------------------------
# Small helpers


def fnum(x):
    s = f"{x:.9g}"
    return s if ("." in s or "e" in s or "n" in s) else s + ".0"


def tvec(v):
    return "[" + ", ".join(fnum(x) for x in v) + "]"


def xvec(v):
    return ", ".join(fnum(x) for x in v)


def png(path, pixels):
    """Write an 8-bit PNG from a uint8 array (H, W), (H, W, 3) or (H, W, 4); row 0 is the top."""
    a = np.ascontiguousarray(pixels, dtype=np.uint8)
    h, w = a.shape[:2]
    channels = 1 if a.ndim == 2 else a.shape[2]
    color_type = {1: 0, 3: 2, 4: 6}[channels]
    raw = b"".join(b"\x00" + a[y].tobytes() for y in range(h))

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, color_type, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def to_blender(p):
    """+Y-up scene coordinates (as the glTF file and Photon have them) to Blender's +Z up."""
    return (p[0], -p[2], p[1])


def from_blender(p):
    return (p[0], p[2], -p[1])


# --------------------------------------------------------------------------------------------
# Blender side


def bpy_module():
    import bpy

    return bpy


def reset():
    bpy = bpy_module()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.resolution_x = RES
    bpy.context.scene.render.resolution_y = RES


def principled(name, base, roughness=1.0, specular_level=0.0, emission=None, strength=1.0):
    """A Principled BSDF material; specular_level 0 makes it Lambertian once exported."""
    bpy = bpy_module()
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Metallic"].default_value = 0.0
    p.inputs["Specular IOR Level"].default_value = specular_level
    if emission is not None:
        p.inputs["Emission Color"].default_value = (*emission, 1.0)
        p.inputs["Emission Strength"].default_value = strength
    return m


def one_sided_lamp(strength):
    """An emissive Principled BSDF with black base colour and Backface Culling on, which the
    exporter writes without doubleSided: a one-sided emitter (its front face, counter-clockwise
    side, emits) that reflects nothing."""
    m = principled("lamp", (0.0, 0.0, 0.0), emission=(1.0, 1.0, 1.0), strength=strength)
    m.use_backface_culling = True
    return m


def mesh_object(name, verts, faces, materials, smooth, uvs=None, face_materials=None, location=None):
    """A mesh object from +Y-up vertices and faces (counter-clockwise seen from the side the
    normal points to); `uvs` per face corner; `face_materials` material index per face."""
    bpy = bpy_module()
    me = bpy.data.meshes.new(name)
    me.from_pydata([to_blender(v) for v in verts], [], [tuple(f) for f in faces])
    for m in materials:
        me.materials.append(m)
    if face_materials is not None:
        for poly, k in zip(me.polygons, face_materials):
            poly.material_index = k
    if uvs is not None:
        layer = me.uv_layers.new(name="UVMap")
        corner = 0
        for f in uvs:
            for uv in f:
                layer.data[corner].uv = uv
                corner += 1
    for poly in me.polygons:
        poly.use_smooth = smooth
    me.validate()
    me.update()
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    if location is not None:
        ob.location = to_blender(location)
    return ob


def quad_object(name, corners, material, uvs=((0, 0), (1, 0), (1, 1), (0, 1))):
    """A quad of two triangles (0 1 2, 0 2 3): Blender's own triangulation is not relied on."""
    return mesh_object(name, corners, [(0, 1, 2), (0, 2, 3)], [material], smooth=False,
                       uvs=[[uvs[0], uvs[1], uvs[2]], [uvs[0], uvs[2], uvs[3]]])


def box_object(name, size, center, rotate_y, material, smooth=False):
    """A box (full sizes), turned about +y by rotate_y degrees (right-handed), flat by default."""
    hx, hy, hz = (s / 2 for s in size)
    c, s = math.cos(math.radians(rotate_y)), math.sin(math.radians(rotate_y))
    verts = []
    for x in (-hx, hx):
        for y in (-hy, hy):
            for z in (-hz, hz):
                verts.append((center[0] + c * x + s * z, center[1] + y, center[2] - s * x + c * z))
    # index = 4 i + 2 j + k for x_i, y_j, z_k; faces outward, counter-clockwise from outside
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    return mesh_object(name, verts, tris, [material], smooth)


def uv_sphere_object(name, center, radius, material, segments=48, rings=24, smooth=True):
    bpy = bpy_module()
    import bmesh

    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius, calc_uvs=True)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])  # fixed triangles, not the exporter's choice
    bm.to_mesh(me)
    bm.free()
    me.materials.append(material)
    for poly in me.polygons:
        poly.use_smooth = smooth
    me.update()
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    ob.location = to_blender(center)
    return ob


def room_object(name, materials, face_materials, smooth, floor=True):
    """The 2 x 2 x 2 room of the other scenes (x, z in [-1, 1], y in [0, 2], open toward +z) as
    one mesh of 8 shared vertices, every wall two triangles, all facing inward. Shaded smooth,
    each corner's normal is the average of the walls meeting there."""
    v = [(x, y, z) for x in (-1.0, 1.0) for y in (0.0, 2.0) for z in (-1.0, 1.0)]
    ix = {p: i for i, p in enumerate(v)}

    def q(*ps):
        a, b, c, d = (ix[p] for p in ps)
        return [(a, b, c), (a, c, d)]

    walls = [
        q((-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)),  # floor, +y
        q((-1, 2, -1), (1, 2, -1), (1, 2, 1), (-1, 2, 1)),  # ceiling, -y
        q((-1, 0, -1), (1, 0, -1), (1, 2, -1), (-1, 2, -1)),  # back, +z
        q((-1, 0, 1), (-1, 0, -1), (-1, 2, -1), (-1, 2, 1)),  # left, +x
        q((1, 0, -1), (1, 0, 1), (1, 2, 1), (1, 2, -1)),  # right, -x
    ]
    if not floor:
        walls, face_materials = walls[1:], face_materials[1:]
    faces = [t for w in walls for t in w]
    fm = [k for k in face_materials for _ in range(2)]
    return mesh_object(name, v, faces, materials, smooth, face_materials=fm)


def camera(position, look_at, fov):
    bpy = bpy_module()
    from mathutils import Vector

    cam = bpy.data.cameras.new("Camera")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(fov)
    ob = bpy.data.objects.new("Camera", cam)
    bpy.context.scene.collection.objects.link(ob)
    ob.location = to_blender(position)
    d = Vector(to_blender(look_at)) - Vector(to_blender(position))
    ob.rotation_euler = d.to_track_quat("-Z", "Z").to_euler()
    bpy.context.scene.camera = ob


def export_glb(path):
    bpy = bpy_module()
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB", export_cameras=True)


def export_ply_parts(ob, out_dir):
    """Write the object's evaluated mesh, one PLY per material slot used, +Y up. Returns
    {material name: file name}."""
    bpy = bpy_module()
    bpy.context.view_layer.update()
    deps = bpy.context.evaluated_depsgraph_get()
    ev = ob.evaluated_get(deps)
    me = ev.to_mesh()
    me.calc_loop_triangles()
    mw = ob.matrix_world
    nw = mw.to_3x3().inverted().transposed()
    normals = me.corner_normals
    uv = me.uv_layers.active.data if me.uv_layers.active else None
    parts = {}
    for tri in me.loop_triangles:
        parts.setdefault(tri.material_index, []).append(tri)
    out = {}
    for k, tris in sorted(parts.items()):
        mat = me.materials[k].name if len(me.materials) else "none"
        verts, index, faces = [], {}, []
        for tri in tris:
            f = []
            for corner, vi in zip(tri.loops, tri.vertices):
                p = from_blender(mw @ me.vertices[vi].co)
                n = nw @ normals[corner].vector
                n = from_blender(n / n.length)
                t = tuple(uv[corner].uv) if uv is not None else (0.0, 0.0)
                key = (p, n, t)
                if key not in index:
                    index[key] = len(verts)
                    verts.append(key)
                f.append(index[key])
            faces.append(f)
        fname = f"{ob.name}-{mat}.ply".lower().replace(" ", "-")
        header = (
            "ply\nformat binary_little_endian 1.0\ncomment written by validation/blender_scenes.py from Blender's mesh, +Y up\n"
            f"element vertex {len(verts)}\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "property float u\nproperty float v\n"
            f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
        )
        with open(os.path.join(out_dir, fname), "wb") as fh:
            fh.write(header.encode("ascii"))
            for p, n, t in verts:
                fh.write(struct.pack("<8f", *p, *n, *t))
            for f in faces:
                fh.write(struct.pack("<B3i", 3, *f))
        out[mat] = fname
    ev.to_mesh_clear()
    return out


# --------------------------------------------------------------------------------------------
# Checks of what the exporter wrote


def read_glb(path):
    with open(path, "rb") as f:
        data = f.read()
    assert data[:4] == b"glTF"
    n = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20 : 20 + n])
    off = 20 + n
    blob = b""
    if off < len(data):
        m = struct.unpack_from("<I", data, off)[0]
        blob = data[off + 8 : off + 8 + m]
    return doc, blob


def accessor(doc, blob, i):
    a = doc["accessors"][i]
    bv = doc["bufferViews"][a["bufferView"]]
    comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    dtype = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}[a["componentType"]]
    start = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
    arr = np.frombuffer(blob, dtype=dtype, count=a["count"] * comps, offset=start)
    return arr.reshape(a["count"], comps) if comps > 1 else arr


def node_matrices(doc):
    """World matrix (4x4, column vectors) of every node with a mesh."""

    def local(nd):
        if "matrix" in nd:
            return np.array(nd["matrix"], dtype=np.float64).reshape(4, 4).T
        t = np.array(nd.get("translation", [0, 0, 0]), dtype=np.float64)
        x, y, z, w = nd.get("rotation", [0, 0, 0, 1])
        r = np.array([
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ])
        s = np.array(nd.get("scale", [1, 1, 1]), dtype=np.float64)
        m = np.eye(4)
        m[:3, :3] = r * s
        m[:3, 3] = t
        return m

    out = {}

    def walk(i, parent):
        nd = doc["nodes"][i]
        m = parent @ local(nd)
        if "mesh" in nd:
            out[i] = m
        for c in nd.get("children", []):
            walk(c, m)

    for root in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        walk(root, np.eye(4))
    return out


def glb_corners(path):
    """{material name: set of rounded (position, normal, uv v-up) triangle corners} in world space."""
    doc, blob = read_glb(path)
    out = {}
    for ni, m in node_matrices(doc).items():
        mesh = doc["meshes"][doc["nodes"][ni]["mesh"]]
        nm = np.linalg.inv(m[:3, :3]).T
        for prim in mesh["primitives"]:
            at = prim["attributes"]
            p = accessor(doc, blob, at["POSITION"]).astype(np.float64) @ m[:3, :3].T + m[:3, 3]
            n = accessor(doc, blob, at["NORMAL"]).astype(np.float64) @ nm.T
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            t = accessor(doc, blob, at["TEXCOORD_0"]).astype(np.float64) if "TEXCOORD_0" in at else np.zeros((len(p), 2))
            if "TEXCOORD_0" in at:
                t = np.stack([t[:, 0], 1.0 - t[:, 1]], axis=1)
            idx = accessor(doc, blob, prim["indices"])
            name = doc["materials"][prim["material"]]["name"] if "material" in prim else "none"
            s = out.setdefault(name, [])
            for i in idx:
                s.append((p[i], n[i], t[i]))
    return out


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    head = data[:end].decode()
    nv = int(head.split("element vertex ")[1].split()[0])
    nf = int(head.split("element face ")[1].split()[0])
    v = np.frombuffer(data, dtype="<f4", count=nv * 8, offset=end).reshape(nv, 8)
    f = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]), count=nf, offset=end + nv * 32)
    return v, f["i"]


def check_plys_against_glb(glb_path, plys):
    """Every PLY corner must be a glb corner of the same material and vice versa (to 1e-5)."""
    g = glb_corners(glb_path)

    def keyset(items):
        return sorted(tuple(np.round(np.concatenate(c), 4)) for c in items)

    per_mat = {}
    for mat, files in plys.items():
        for fn in files:
            v, f = read_ply(fn)
            per_mat.setdefault(mat, []).extend(
                (v[i, :3].astype(np.float64), v[i, 3:6].astype(np.float64), v[i, 6:8].astype(np.float64))
                for tri in f for i in tri
            )
    for mat, corners in per_mat.items():
        a, b = keyset(corners), keyset(g.get(mat, []))
        if len(a) != len(b):
            raise SystemExit(f"{glb_path}: material {mat}: {len(a)} PLY corners but {len(b)} in the glb")
        diff = max(np.max(np.abs(np.array(x) - np.array(y))) for x, y in zip(a, b))
        if diff > 2e-4:
            raise SystemExit(f"{glb_path}: material {mat}: PLY and glb corners differ by {diff}")
    missing = set(g) - set(per_mat)
    if missing:
        raise SystemExit(f"{glb_path}: materials {missing} have no PLY")


def glb_summary(path):
    doc, _ = read_glb(path)
    return doc


# --------------------------------------------------------------------------------------------
# Writing the TOML and XML twins


class Twin:
    def __init__(self, name, comment, spp):
        self.name = name
        self.dir = os.path.join(HERE, name)
        os.makedirs(self.dir, exist_ok=True)
        self.comment = comment.strip()
        self.spp = spp
        self.integrator = "path"
        self.cam = None
        self.bsdfs = []  # XML lines
        self.shapes = []  # XML blocks
        self.media = []
        self.plys = {}  # material -> [ply paths] for the check

    def set_camera(self, position, look_at, fov):
        self.cam = (position, look_at, fov)
        camera(position, look_at, fov)

    def ply_shape(self, file, bsdf_xml, extra=""):
        self.shapes.append(
            f'<shape type="ply">\n    <string name="filename" value="{file}"/>\n{extra}    {bsdf_xml}\n</shape>'
        )

    def add_object(self, ob, bsdf_for):
        """The object's PLY parts, each with the Mitsuba BSDF XML bsdf_for(material name)."""
        for mat, fn in export_ply_parts(ob, self.dir).items():
            self.plys.setdefault(mat, []).append(os.path.join(self.dir, fn))
            self.ply_shape(fn, bsdf_for(mat))

    def add_two_sided_emitter(self, ob, radiance, bsdf_xml):
        """A doubleSided emissive mesh (planar): two one-sided copies facing away from each
        other, EMITTER_GAP either side of the surface."""
        for mat, fn in export_ply_parts(ob, self.dir).items():
            self.plys.setdefault(mat, []).append(os.path.join(self.dir, fn))
            v, _ = read_ply(os.path.join(self.dir, fn))
            n = v[0, 3:6].astype(np.float64)
            for side in (1, -1):
                t = n * EMITTER_GAP * side
                extra = f'    <transform name="to_world"><translate x="{fnum(t[0])}" y="{fnum(t[1])}" z="{fnum(t[2])}"/></transform>\n'
                if side < 0:
                    extra += '    <boolean name="flip_normals" value="true"/>\n'
                extra += f'    <emitter type="area"><rgb name="radiance" value="{xvec(radiance)}"/></emitter>\n'
                self.ply_shape(fn, bsdf_xml, extra)

    def add_one_sided_emitter(self, ob, radiance):
        """A one-sided emissive mesh with a black base colour: Mitsuba's area emitter on the
        mesh, black diffuse BSDF (the glb's front face is the PLY's normal side)."""
        for mat, fn in export_ply_parts(ob, self.dir).items():
            self.plys.setdefault(mat, []).append(os.path.join(self.dir, fn))
            extra = f'    <emitter type="area"><rgb name="radiance" value="{xvec(radiance)}"/></emitter>\n'
            self.ply_shape(fn, '<bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>', extra)

    def write(self):
        export_glb(os.path.join(self.dir, f"{self.name}.glb"))
        check_plys_against_glb(os.path.join(self.dir, f"{self.name}.glb"), self.plys)
        position, look_at, fov = self.cam
        comment = "\n".join("# " + line if line else "#" for line in self.comment.splitlines())
        toml = f"""{comment}
# Written by validation/blender_scenes.py (edit there): {self.name}.glb is Blender's glTF export;
# Mitsuba twin: {self.name}.xml (the same meshes as PLY), reference: reference.exr.
name = "{self.name}"

[camera]
position = {tvec(position)}
look_at = {tvec(look_at)}
up = [0.0, 1.0, 0.0]
fov = {fnum(fov)}
resolution = [{RES}, {RES}]

[render]
spp = 16
filter = "box"

# The whole Blender export: its materials, emission and normals as the file has them.
[[shapes]]
type = "mesh"
file = "{self.name}.glb"
"""
        with open(os.path.join(self.dir, f"{self.name}.toml"), "w") as f:
            f.write(toml)
        xml_comment = "\n".join("  " + line for line in self.comment.splitlines())
        integrator = f'<integrator type="{self.integrator}"><integer name="max_depth" value="-1"/></integrator>'
        xml = f"""<?xml version="1.0" encoding="utf-8"?>
<!--
{xml_comment}
  Written by validation/blender_scenes.py (edit there); Photon twin: {self.name}.toml (reading
  {self.name}.glb, Blender's glTF export; the PLY files are the same meshes).
  Reference: python validation/make_references.py {self.name}
-->
<scene version="3.0.0">
<default name="spp" value="{self.spp}"/>
{integrator}
<sensor type="perspective">
    <float name="fov" value="{fnum(fov)}"/>
    <string name="fov_axis" value="y"/>
    <float name="near_clip" value="0.001"/>
    <float name="far_clip" value="1e7"/>
    <transform name="to_world"><lookat origin="{xvec(position)}" target="{xvec(look_at)}" up="0.0, 1.0, 0.0"/></transform>
    <sampler type="multijitter"><integer name="sample_count" value="$spp"/></sampler>
    <film type="hdrfilm">
        <integer name="width" value="{RES}"/>
        <integer name="height" value="{RES}"/>
        <string name="pixel_format" value="rgb"/>
        <rfilter type="box"/>
    </film>
</sensor>
"""
        xml += "".join(line + "\n" for line in self.media)
        xml += "".join(line + "\n" for line in self.bsdfs)
        xml += "".join(s + "\n" for s in self.shapes)
        xml += "</scene>\n"
        with open(os.path.join(self.dir, f"{self.name}.xml"), "w") as f:
            f.write(xml)
        print(f"{self.name}: wrote {self.name}.glb, .toml, .xml and {sum(len(v) for v in self.plys.values())} PLY files")


def diffuse_bsdf(id_, rgb):
    return f'<bsdf type="twosided" id="{id_}"><bsdf type="diffuse"><rgb name="reflectance" value="{xvec(rgb)}"/></bsdf></bsdf>'


def ref(id_):
    return f'<ref id="{id_}"/>'


def check_materials(glb, expect):
    """expect: {material name: dict of JSON paths -> expected value (None: must exist)}."""
    doc = glb_summary(glb)
    mats = {m["name"]: m for m in doc["materials"]}
    for name, checks in expect.items():
        m = mats[name]
        for path, want in checks.items():
            cur = m
            for k in path.split("/"):
                if not isinstance(cur, dict) or k not in cur:
                    raise SystemExit(f"{glb}: material {name} lacks {path}: {json.dumps(m)}")
                cur = cur[k]
            if want is not None and cur != want:
                raise SystemExit(f"{glb}: material {name}: {path} = {cur}, expected {want}")
    return doc


# --------------------------------------------------------------------------------------------
# The scenes

STD_CAMERA = ((0.0, 0.95, 2.9), (0.0, 0.55, 0.0), 39.3)


def smooth_box():
    reset()
    s = Twin("smooth-box", """
A Cornell-like box (2 x 2 x 2, white, red and green walls) made in Blender as one mesh of 8
shared vertices, every wall two triangles, shaded smooth: the exporter writes corner-averaged
vertex normals, (+-0.577, +-0.577, +-0.577) at the back corners and (+-0.707, +-0.707, 0) at the
front ones, so the shading normal turns up to 55 degrees from the wall. A flat-shaded white block
and a smooth UV sphere (48 x 24) stand on the floor. Light: an emissive 0.5 x 0.5 quad (Principled
BSDF: base colour 0.8, emission strength 15, double-sided as Blender exports it) 30 cm below the
ceiling, out of the camera's frame. Every surface is Lambertian (Specular IOR Level 0).
""", spp=24576)
    white = principled("white", WHITE)
    red = principled("red", RED)
    green = principled("green", GREEN)
    lamp = principled("lamp", (0.8, 0.8, 0.8), emission=(1.0, 1.0, 1.0), strength=15.0)
    room = room_object("room", [white, red, green], [0, 0, 0, 1, 2], smooth=True)
    block = box_object("block", (0.55, 0.55, 0.55), (0.35, 0.275, 0.3), -17.0, white)
    ball = uv_sphere_object("ball", (-0.4, 0.35, -0.3), 0.35, white)
    light = quad_object("light", [(-0.25, 1.7, -0.25), (0.25, 1.7, -0.25), (0.25, 1.7, 0.25), (-0.25, 1.7, 0.25)], lamp)
    s.set_camera(*STD_CAMERA)
    s.bsdfs += [diffuse_bsdf("white", WHITE), diffuse_bsdf("red", RED), diffuse_bsdf("green", GREEN),
                diffuse_bsdf("lamp", (0.8, 0.8, 0.8))]
    for ob in (room, block, ball):
        s.add_object(ob, ref)
    s.add_two_sided_emitter(light, (15.0, 15.0, 15.0), ref("lamp"))
    s.write()
    glb = os.path.join(s.dir, "smooth-box.glb")
    check_materials(glb, {
        "white": {"extensions/KHR_materials_specular/specularFactor": 0.0},
        "lamp": {"emissiveFactor": [1.0, 1.0, 1.0], "extensions/KHR_materials_emissive_strength/emissiveStrength": 15.0,
                 "doubleSided": True},
    })


def flush_light():
    reset()
    s = Twin("flush-light", """
A white box (2 x 2 x 2, open toward the camera, flat-shaded: the exporter writes face normals)
with a 0.5 x 0.5 emissive quad 1 cm below the ceiling as Blender exports a ceiling panel: a
Principled BSDF with base colour 0.8 (it reflects) and emission strength 8, double-sided, so its
top face lights the ceiling 1 cm above it. A white block on the floor; everything flat-shaded (no
shading normals: Mitsuba's light tracer would need their adjoint correction). The
camera, low in the open front and looking up, sees the ceiling and the light's lower face with
its back and side edges (its pixels carry part of the image's mean: the emitter share in
validation/README.md); the front edge, where the gap opens toward the camera and the ceiling lit
from 1 cm is seen (next-event estimation's worst case), is just above the frame. Every surface
is Lambertian (Specular IOR Level 0).
The light from the top face leaves the 1 cm gap as a thin bright slit that camera paths find
only by chance: the noisiest reference per sample (Mitsuba's light tracer, `ptracer`, is 7x
less noisy for the time but came out 0.25% darker than both Mitsuba's and Photon's path tracers,
uniformly over the room and 1.2% on the pixels at the panel's edge; not used).
""", spp=24576)
    white = principled("white", WHITE)
    lamp = principled("lamp", (0.8, 0.8, 0.8), emission=(1.0, 1.0, 1.0), strength=8.0)
    room = room_object("room", [white], [0, 0, 0, 0, 0], smooth=False)
    block = box_object("block", (0.5, 0.8, 0.5), (-0.4, 0.4, -0.35), 20.0, white)
    light = quad_object("light", [(-0.25, 1.99, -0.25), (0.25, 1.99, -0.25), (0.25, 1.99, 0.25), (-0.25, 1.99, 0.25)], lamp)
    s.set_camera((0.0, 0.9, 1.3), (0.0, 1.5, 0.0), 40.0)
    s.bsdfs += [diffuse_bsdf("white", WHITE), diffuse_bsdf("lamp", (0.8, 0.8, 0.8))]
    for ob in (room, block):
        s.add_object(ob, ref)
    s.add_two_sided_emitter(light, (8.0, 8.0, 8.0), ref("lamp"))
    s.write()
    check_materials(os.path.join(s.dir, "flush-light.glb"), {
        "lamp": {"emissiveFactor": [1.0, 1.0, 1.0], "extensions/KHR_materials_emissive_strength/emissiveStrength": 8.0,
                 "doubleSided": True},
    })


def textures_for_normal_mapped(out_dir):
    """arrows.png: four pale quadrants, a dark arrow toward +v (up the image) and a dark square
    in the top-left quadrant, so that a flip or a turn of the image shows; bumps-normal.png: a
    tangent-space normal map (+y = +v, OpenGL/glTF) of 4 x 4 bumps, slopes up to 27 degrees."""
    n = 128
    u = (np.arange(n) + 0.5) / n
    v = 1.0 - (np.arange(n) + 0.5) / n  # row 0 is the top of the image: v = 1
    U, V = np.meshgrid(u, v)
    img = np.zeros((n, n, 3))
    img[(U < 0.5) & (V >= 0.5)] = (0.95, 0.55, 0.5)
    img[(U >= 0.5) & (V >= 0.5)] = (0.55, 0.9, 0.5)
    img[(U < 0.5) & (V < 0.5)] = (0.5, 0.65, 0.95)
    img[(U >= 0.5) & (V < 0.5)] = (0.95, 0.9, 0.45)
    dark = (0.08, 0.08, 0.1)
    shaft = (np.abs(U - 0.5) < 0.06) & (V > 0.12) & (V < 0.66)
    head = (V >= 0.66) & (V < 0.9) & (np.abs(U - 0.5) < 0.2 * (0.9 - V) / 0.24)
    spot = (U > 0.08) & (U < 0.22) & (V > 0.76) & (V < 0.9)
    img[shaft | head | spot] = dark
    png(os.path.join(out_dir, "arrows.png"), np.round(img * 255))
    f, slope = 4, 0.5
    a = 2 * np.pi * f
    nx = -slope * np.cos(a * U) * np.sin(a * V)
    ny = -slope * np.sin(a * U) * np.cos(a * V)
    nn = np.stack([nx, ny, np.ones_like(nx)], axis=2)
    nn /= np.linalg.norm(nn, axis=2, keepdims=True)
    png(os.path.join(out_dir, "bumps-normal.png"), np.round((nn * 0.5 + 0.5) * 255))


def normal_mapped():
    reset()
    bpy = bpy_module()
    s = Twin("normal-mapped", """
A 2 x 2 floor in a white room (open toward the camera), made in Blender with an image texture
(arrows.png: an arrow toward the image's top, a square in its top-left quadrant) behind a Mapping
node (Point: location (0.3, 0.2), rotation 30 degrees, scale (2, 1.5)), which the glTF exporter
writes as KHR_texture_transform on the base colour texture only, and a Normal Map node (tangent
space, strength 1) reading bumps-normal.png on the plain UVs (4 x 4 bumps). The floor's UVs run
0..1 across it, u toward +x, v toward -z. Lambertian (Specular IOR Level 0). Light: an emissive
0.5 x 0.5 quad (strength 15; black base colour and Backface Culling, so one-sided, facing down)
30 cm below the ceiling toward the back left, out of the frame. Mitsuba: the bitmap's to_uv is the Mapping node's transform followed by (u, 1 - v);
the normal map is Mitsuba's `normalmap` on the plain UVs.
""", spp=8192)
    textures_for_normal_mapped(s.dir)
    white = principled("white", WHITE)
    lamp = one_sided_lamp(15.0)
    floor_mat = principled("floor", (1.0, 1.0, 1.0))
    nt = floor_mat.node_tree
    p = nt.nodes["Principled BSDF"]
    coord = nt.nodes.new("ShaderNodeTexCoord")
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    loc, rot, scale = (0.3, 0.2), 30.0, (2.0, 1.5)
    mapping.inputs["Location"].default_value = (loc[0], loc[1], 0.0)
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(rot))
    mapping.inputs["Scale"].default_value = (scale[0], scale[1], 1.0)
    arrows = nt.nodes.new("ShaderNodeTexImage")
    arrows.image = bpy.data.images.load(os.path.join(s.dir, "arrows.png"))
    arrows.interpolation = "Linear"
    nt.links.new(coord.outputs["UV"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], arrows.inputs["Vector"])
    nt.links.new(arrows.outputs["Color"], p.inputs["Base Color"])
    bumps = nt.nodes.new("ShaderNodeTexImage")
    bumps.image = bpy.data.images.load(os.path.join(s.dir, "bumps-normal.png"))
    bumps.image.colorspace_settings.name = "Non-Color"
    bumps.interpolation = "Linear"
    nmap = nt.nodes.new("ShaderNodeNormalMap")
    nmap.space = "TANGENT"
    nmap.inputs["Strength"].default_value = 1.0
    nt.links.new(coord.outputs["UV"], bumps.inputs["Vector"])
    nt.links.new(bumps.outputs["Color"], nmap.inputs["Color"])
    nt.links.new(nmap.outputs["Normal"], p.inputs["Normal"])

    room = room_object("room", [white], [0, 0, 0, 0, 0], smooth=False, floor=False)
    floor = quad_object("floor", [(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)], floor_mat)
    light = quad_object("light", [(-0.55, 1.7, -0.55), (-0.05, 1.7, -0.55), (-0.05, 1.7, -0.05), (-0.55, 1.7, -0.05)], lamp)
    s.set_camera((0.0, 1.5, 2.6), (0.0, 0.2, -0.2), 40.0)
    # Blender's Point mapping: t = R(rot) (S uv) + loc, in Blender's (v up) image coordinates;
    # Mitsuba's bitmap reads (t.x, 1 - t.y).
    c, sn = math.cos(math.radians(rot)), math.sin(math.radians(rot))
    m = [[scale[0] * c, -scale[1] * sn, loc[0]], [scale[0] * sn, scale[1] * c, loc[1]]]
    to_uv = [m[0], [-m[1][0], -m[1][1], 1.0 - m[1][2]]]
    to_uv_xml = (f'<transform name="to_uv"><matrix value="{fnum(to_uv[0][0])} {fnum(to_uv[0][1])} 0 {fnum(to_uv[0][2])} '
                 f'{fnum(to_uv[1][0])} {fnum(to_uv[1][1])} 0 {fnum(to_uv[1][2])} 0 0 1 0 0 0 0 1"/></transform>')
    flip = '<transform name="to_uv"><scale x="1" y="-1"/><translate x="0" y="1"/></transform>'
    s.bsdfs += [
        diffuse_bsdf("white", WHITE),
        '<bsdf type="twosided" id="floor"><bsdf type="normalmap">'
        '<texture type="bitmap" name="normalmap"><string name="filename" value="bumps-normal.png"/>'
        '<boolean name="raw" value="true"/><string name="filter_type" value="bilinear"/><string name="wrap_mode" value="repeat"/>'
        f'{flip}</texture>'
        '<bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="arrows.png"/>'
        '<string name="filter_type" value="bilinear"/><string name="wrap_mode" value="repeat"/>'
        f'{to_uv_xml}</texture></bsdf></bsdf></bsdf>',
    ]
    s.add_object(room, ref)
    s.add_object(floor, ref)
    s.add_one_sided_emitter(light, (15.0, 15.0, 15.0))
    s.write()
    doc = check_materials(os.path.join(s.dir, "normal-mapped.glb"), {
        "floor": {"pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform": None,
                  "normalTexture": None},
    })
    fm = [m for m in doc["materials"] if m["name"] == "floor"][0]
    print("  floor:", json.dumps(fm))


def fence_textures(out_dir):
    """fence.png (RGBA, for Blender and the glb): a lattice, bars 16 texels wide every 64 (128 x
    128: 2 x 2 windows), alpha exactly 0 or 1, one wood colour; fence-rgb.png and fence-alpha.png:
    its colour and its alpha for Mitsuba."""
    n = 128
    x = np.arange(n)
    X, Y = np.meshgrid(x, x)
    alpha = ((X % 64 < 16) | (Y % 64 < 16)).astype(np.uint8) * 255
    rgb = np.zeros((n, n, 3), np.uint8)
    rgb[:] = (196, 140, 90)
    png(os.path.join(out_dir, "fence.png"), np.dstack([rgb, alpha]))
    png(os.path.join(out_dir, "fence-rgb.png"), rgb)
    png(os.path.join(out_dir, "fence-alpha.png"), alpha)


def alpha_fence():
    reset()
    bpy = bpy_module()
    s = Twin("alpha-fence", """
A white room (open toward the camera) with a horizontal 0.8 x 0.8 card at height 0.9 between a
light and the floor: its Principled BSDF reads fence.png, a wooden lattice whose PNG alpha is
exactly 0 or 1 (bars 16 texels wide every 64 of 128: 2 x 2 windows of 0.3 m), with Alpha through
a Math Round node, which Blender's glTF exporter writes as alphaMode MASK, alphaCutoff 0.5 (and,
the image node set to Closest, a NEAREST sampler). It casts a lattice shadow on the floor, and a
glass sphere on the floor (radius 0.2, Principled transmission 1, roughness 0, IOR 1.5, smooth UV
sphere 64 x 32) under a window focuses the light that came through it into a caustic. Light: an
emissive 0.3 x 0.3 quad (strength 40; black base colour and Backface Culling, so one-sided,
facing down) at height 1.9 toward the back left, out of the frame (the camera looks down from
1.75). Mitsuba: `mask` around the card's BSDF with the alpha as opacity (nearest texel;
binary, so MASK and BLEND agree), integrator `volpath`, whose shadow rays pass through the
transparent texels (`path` would only find the light through them by BSDF sampling).
""", spp=6144)
    s.integrator = "volpath"
    fence_textures(s.dir)
    white = principled("white", WHITE)
    lamp = one_sided_lamp(40.0)
    card = principled("fence", (1.0, 1.0, 1.0))
    nt = card.node_tree
    p = nt.nodes["Principled BSDF"]
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = bpy.data.images.load(os.path.join(s.dir, "fence.png"))
    tex.interpolation = "Closest"
    rnd = nt.nodes.new("ShaderNodeMath")
    rnd.operation = "ROUND"
    nt.links.new(tex.outputs["Color"], p.inputs["Base Color"])
    nt.links.new(tex.outputs["Alpha"], rnd.inputs[0])
    nt.links.new(rnd.outputs["Value"], p.inputs["Alpha"])
    glass = principled("glass", (1.0, 1.0, 1.0), roughness=0.0, specular_level=0.5)
    glass.node_tree.nodes["Principled BSDF"].inputs["Transmission Weight"].default_value = 1.0
    glass.node_tree.nodes["Principled BSDF"].inputs["IOR"].default_value = 1.5

    room = room_object("room", [white], [0, 0, 0, 0, 0], smooth=False)
    fence = quad_object("card", [(-0.4, 0.9, 0.2), (0.4, 0.9, 0.2), (0.4, 0.9, -0.6), (-0.4, 0.9, -0.6)], card)
    ball = uv_sphere_object("ball", (0.3, 0.2, 0.05), 0.2, glass, segments=64, rings=32)
    light = quad_object("light", [(-0.45, 1.9, -0.65), (-0.15, 1.9, -0.65), (-0.15, 1.9, -0.35), (-0.45, 1.9, -0.35)], lamp)
    s.set_camera((0.0, 1.75, 2.2), (0.0, 0.3, -0.2), 45.0)
    s.bsdfs += [
        diffuse_bsdf("white", WHITE),
        '<bsdf type="dielectric" id="glass"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1.0"/></bsdf>',
        '<bsdf type="mask" id="fence"><texture type="bitmap" name="opacity"><string name="filename" value="fence-alpha.png"/>'
        '<boolean name="raw" value="true"/><string name="filter_type" value="nearest"/><string name="wrap_mode" value="repeat"/>'
        '<transform name="to_uv"><scale x="1" y="-1"/><translate x="0" y="1"/></transform></texture>'
        '<bsdf type="twosided"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="fence-rgb.png"/>'
        '<string name="filter_type" value="bilinear"/><string name="wrap_mode" value="repeat"/>'
        '<transform name="to_uv"><scale x="1" y="-1"/><translate x="0" y="1"/></transform></texture></bsdf></bsdf></bsdf>',
    ]
    s.add_object(room, ref)
    s.add_object(fence, ref)
    s.add_object(ball, ref)
    s.add_one_sided_emitter(light, (40.0, 40.0, 40.0))
    s.write()
    doc = check_materials(os.path.join(s.dir, "alpha-fence.glb"), {
        "fence": {"alphaMode": "MASK", "pbrMetallicRoughness/baseColorTexture": None},
        "glass": {"extensions/KHR_materials_transmission/transmissionFactor": 1.0},
    })
    for m in doc["materials"]:
        print("  ", json.dumps(m))


def absorbing_glass():
    reset()
    bpy = bpy_module()
    color, distance, thickness = (0.25, 0.6, 0.85), 0.5, 0.5
    s = Twin("absorbing-glass", f"""
Absorbing glass in a white room (open toward the camera): a smooth glass sphere (radius 0.35,
UV sphere 64 x 32) and a flat-shaded glass block (0.4 x 0.6 x 0.4) made in Blender with a
Principled BSDF (transmission 1, roughness 0, IOR 1.5, white) and a Volume Absorption node (colour
{color}, density {1 / distance:g}) on the material output's volume, plus the exporter's "glTF
Material Output" group with Thickness {thickness}: Blender's glTF exporter writes
KHR_materials_volume (attenuationColor = the absorption colour, attenuationDistance = 1 / density,
thicknessFactor) and, for a volume, doubleSided false. Light: an emissive 1 x 1 quad (strength
5; black base colour and Backface Culling, so one-sided, facing down) 10 cm below the ceiling,
out of the frame (large, so that paths through the glass find it often). Mitsuba: `dielectric`
(int_ior 1.5, ext_ior 1) around an interior `homogeneous` medium, albedo 0, sigma_t =
-ln(attenuationColor) / attenuationDistance per channel (Beer-Lambert as KHR_materials_volume
defines it), integrator `volpath`.
""", spp=12288)
    s.integrator = "volpath"
    white = principled("white", WHITE)
    lamp = one_sided_lamp(5.0)
    glass = principled("tinted-glass", (1.0, 1.0, 1.0), roughness=0.0, specular_level=0.5)
    nt = glass.node_tree
    p = nt.nodes["Principled BSDF"]
    p.inputs["Transmission Weight"].default_value = 1.0
    p.inputs["IOR"].default_value = 1.5
    absorb = nt.nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Color"].default_value = (*color, 1.0)
    absorb.inputs["Density"].default_value = 1.0 / distance
    out = nt.nodes["Material Output"]
    nt.links.new(absorb.outputs["Volume"], out.inputs["Volume"])
    from io_scene_gltf2.blender.com.material_helpers import create_settings_group, get_gltf_node_name

    group = create_settings_group(get_gltf_node_name())
    gnode = nt.nodes.new("ShaderNodeGroup")
    gnode.node_tree = group
    gnode.inputs["Thickness"].default_value = thickness

    room = room_object("room", [white], [0, 0, 0, 0, 0], smooth=False)
    ball = uv_sphere_object("ball", (-0.4, 0.35, -0.2), 0.35, glass, segments=64, rings=32)
    block = box_object("block", (0.4, 0.6, 0.4), (0.4, 0.3, 0.25), 25.0, glass)
    light = quad_object("light", [(-0.5, 1.9, -0.6), (0.5, 1.9, -0.6), (0.5, 1.9, 0.4), (-0.5, 1.9, 0.4)], lamp)
    s.set_camera(*STD_CAMERA)
    sigma = [-math.log(c) / distance for c in color]
    scale = max(sigma)  # Mitsuba's RGB sigma_t must lie in [0, 1]: sigma_t = scale * rgb
    s.media.append(
        f'<medium type="homogeneous" id="absorbing"><rgb name="sigma_t" value="{xvec([x / scale for x in sigma])}"/>'
        f'<float name="scale" value="{fnum(scale)}"/><rgb name="albedo" value="0, 0, 0"/></medium>')
    s.bsdfs += [
        diffuse_bsdf("white", WHITE),
        '<bsdf type="dielectric" id="glass"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1.0"/></bsdf>',
    ]
    s.add_object(room, ref)
    for ob in (ball, block):
        s.add_object(ob, lambda mat: ref("glass") + '\n    <ref name="interior" id="absorbing"/>')
    s.add_one_sided_emitter(light, (5.0, 5.0, 5.0))
    s.write()
    doc = check_materials(os.path.join(s.dir, "absorbing-glass.glb"), {
        "tinted-glass": {"extensions/KHR_materials_volume/attenuationColor": None,
                         "extensions/KHR_materials_volume/attenuationDistance": None,
                         "extensions/KHR_materials_volume/thicknessFactor": thickness,
                         "extensions/KHR_materials_transmission/transmissionFactor": 1.0},
    })
    for m in doc["materials"]:
        print("  ", json.dumps(m))


def rough_glass():
    reset()
    s = Twin("rough-glass", """
Rough glass as Blender exports it: a Cornell-like box (white, red and green walls, flat-shaded)
with a smooth UV sphere (radius 0.4, 64 x 32, shaded smooth) of Principled BSDF glass
(transmission 1, IOR 1.5, white, Roughness 0.2828: the exporter writes roughnessFactor, and
GGX alpha = roughness^2 = 0.08) standing on the floor, casting a blurred caustic. Light: an
emissive 0.8 x 0.8 quad (strength 10; black base colour and Backface Culling, so one-sided,
facing down) 5 cm below the ceiling, out of the frame. Mitsuba: `roughdielectric` (ggx, alpha
0.08, int_ior 1.5, ext_ior 1) on the same mesh with the same vertex normals.
""", spp=16384)
    white = principled("white", WHITE)
    red = principled("red", RED)
    green = principled("green", GREEN)
    lamp = one_sided_lamp(10.0)
    glass = principled("rough-glass", (1.0, 1.0, 1.0), roughness=math.sqrt(0.08), specular_level=0.5)
    p = glass.node_tree.nodes["Principled BSDF"]
    p.inputs["Transmission Weight"].default_value = 1.0
    p.inputs["IOR"].default_value = 1.5
    room = room_object("room", [white, red, green], [0, 0, 0, 1, 2], smooth=False)
    ball = uv_sphere_object("ball", (0.0, 0.4, -0.2), 0.4, glass, segments=64, rings=32)
    light = quad_object("light", [(-0.4, 1.95, -0.4), (0.4, 1.95, -0.4), (0.4, 1.95, 0.4), (-0.4, 1.95, 0.4)], lamp)
    s.set_camera(*STD_CAMERA)
    s.bsdfs += [
        diffuse_bsdf("white", WHITE), diffuse_bsdf("red", RED), diffuse_bsdf("green", GREEN),
        '<bsdf type="roughdielectric" id="rough-glass"><string name="distribution" value="ggx"/>'
        '<float name="alpha" value="0.08"/><float name="int_ior" value="1.5"/><float name="ext_ior" value="1.0"/></bsdf>',
    ]
    for ob in (room, ball):
        s.add_object(ob, ref)
    s.add_one_sided_emitter(light, (10.0, 10.0, 10.0))
    s.write()
    check_materials(os.path.join(s.dir, "rough-glass.glb"), {
        "rough-glass": {"extensions/KHR_materials_transmission/transmissionFactor": 1.0,
                        "pbrMetallicRoughness/roughnessFactor": None},
    })


SCENES = {
    "smooth-box": smooth_box,
    "flush-light": flush_light,
    "normal-mapped": normal_mapped,
    "alpha-fence": alpha_fence,
    "absorbing-glass": absorbing_glass,
    "rough-glass": rough_glass,
}


def main(names):
    names = names or list(SCENES)
    unknown = [n for n in names if n not in SCENES]
    if unknown:
        raise SystemExit(f"unknown scene(s) {unknown}; known: {', '.join(SCENES)}")
    for n in names:
        SCENES[n]()


if __name__ == "__main__":
    main(sys.argv[1:])
