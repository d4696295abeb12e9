"""Photon as a Blender render engine.

Install the `photon_render` Python module into Blender's Python (see README.md, "Blender"), then
install this folder as an add-on. Pick "Photon" as the render engine; F12 renders.

How the Blender scene becomes a Photon scene:

- geometry and materials go through Blender's own glTF exporter (modifiers applied,
  transforms, Principled BSDF → glTF PBR: base colour, metallic, roughness, normal maps,
  transmission, emission), which Photon's glTF importer reads;
- dispersion: Blender's shader nodes have none (no Dispersion input on the Principled or Glass
  BSDF in 4.5 or 5.0; Cycles does not disperse), and its glTF exporter of 4.5 and 5.0 writes no
  KHR_materials_dispersion. Newer glTF exporters take it from a "Dispersion" input of the
  material's "glTF Material Output" node group (the group that holds Thickness), in glTF's own
  units, 20 / V_d (V_d the Abbe number; the IOR is n_d). The add-on reads that same input and
  writes the extension into the export where the exporter did not, so Photon's glass disperses
  (in spectral rendering: the Spectral setting) on any Blender;
- the camera (perspective), point, spot, sun and area lights and the world colour are read
  directly, in Photon's units: a point or area light of power P W emits P W (an area light
  is one-sided and Lambertian, radiance P / (π·area)); a spot light has the intensity
  P / 4π W/sr of the point light it is cut from; a sun's strength is its irradiance in W/m²;
  the world colour × strength is a uniform sky of that radiance.

- volumes: a Volume Scatter, Volume Absorption or Principled Volume (or a sum of them by Add
  Shader) on the World's Volume output fills the scene (`medium`); on the Volume output of an
  object's material with nothing on its Surface output, the object becomes an invisible
  boundary (`interior`) around that medium, written as a PLY mesh beside the scene. Cycles'
  coefficients per metre: Scatter σs = colour·density, Absorption σa = (1 − colour)·density,
  Principled σs = colour·density and σa = max(1 − colour, 0)·max(1 − √absorption colour,
  0)·density; Anisotropy is the Henyey–Greenstein g.

Not mapped (say so in the render's report): world node trees beyond a Background colour,
light textures and nodes, spot light shapes other than round, area shapes 'ELLIPSE' (a disk
is used) and 'RECTANGLE' with unequal sides (a rectangle is used, both fine), volume grids,
textures and emission (the density and colours the nodes hold are used), a volume inside an
object that also has a surface, hair, orthographic and panoramic cameras, depth of field,
motion blur.
"""

bl_info = {
    "name": "Photon",
    "author": "Photon developers",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "Render Properties > Render Engine > Photon",
    "description": "Photon: photon-mapping global illumination",
    "category": "Render",
}

import json
import math
import os
import shutil
import struct
import tempfile

import bpy
import mathutils

# Blender is z-up; glTF (and so the exported meshes) y-up: (x, y, z) → (x, z, −y).


def y_up(v):
    return (v[0], v[2], -v[1])


def fmt(v):
    return "[" + ", ".join(f"{float(x):.9g}" for x in v) + "]"


TOML_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f",
                "\r": "\\r"}


def toml_string(text):
    """`text` as a TOML basic string: quotes, backslashes and control characters escaped
    (a lone surrogate, which UTF-8 cannot hold, becomes U+FFFD)."""
    out = []
    for ch in text:
        if ch in TOML_ESCAPES:
            out.append(TOML_ESCAPES[ch])
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04X}")
        elif 0xD800 <= ord(ch) <= 0xDFFF:
            out.append("\ufffd")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


# The integrators that render in passes, and those of them that trace photons per pass.
PHOTON_PASSES = ("sppm", "ppm")
PROGRESSIVE = PHOTON_PASSES + ("vcm", "bdpt", "lighttrace")


class PhotonRenderSettings(bpy.types.PropertyGroup):
    integrator: bpy.props.EnumProperty(
        name="Integrator",
        items=[
            ("sppm", "SPPM", "Stochastic progressive photon mapping: converges, progressive"),
            ("ppm", "PPM", "Probabilistic progressive photon mapping: independent passes"),
            (
                "vcm",
                "VCM",
                "Vertex connection and merging: bidirectional paths and photon merging, progressive",
            ),
            ("bdpt", "Bidirectional", "Bidirectional path tracing, progressive"),
            ("lighttrace", "Light tracing", "Light paths connected to the camera, progressive"),
            ("photon", "Photon mapping", "Two-pass photon mapping with final gathering"),
            ("path", "Path tracing", "Unidirectional path tracing: the reference"),
            ("direct", "Direct light", "Ray-traced direct light only"),
        ],
        default="sppm",
    )
    passes: bpy.props.IntProperty(name="Passes", default=32, min=1, max=1_000_000)
    photons_per_pass: bpy.props.IntProperty(
        name="Photons per Pass", default=100_000, min=1000, max=100_000_000
    )
    spp: bpy.props.IntProperty(name="Samples", default=0, min=0, max=65536,
                               description="Samples per pixel; 0: the integrator's default")
    photons: bpy.props.IntProperty(name="Photons", default=250_000, min=1000)
    max_depth: bpy.props.IntProperty(name="Max Depth", default=0, min=0, max=1024,
                                     description="Maximum bounces; 0: the integrator's default")
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0)
    threads: bpy.props.IntProperty(name="Threads", default=0, min=0, max=256,
                                   description="0: one per core")
    spectral: bpy.props.BoolProperty(
        name="Spectral", default=False,
        description="Render wavelengths, not RGB channels: glass with dispersion disperses")


def resolution(scene):
    r = scene.render
    return (int(r.resolution_x * r.resolution_percentage / 100),
            int(r.resolution_y * r.resolution_percentage / 100))


def camera_toml(scene):
    cam = scene.camera
    if cam is None or cam.data.type != "PERSP":
        raise RuntimeError("Photon renders through a perspective camera; the scene has none")
    m = cam.matrix_world
    position = m.translation
    forward = (m.to_3x3() @ mathutils.Vector((0.0, 0.0, -1.0))).normalized()
    up = (m.to_3x3() @ mathutils.Vector((0.0, 1.0, 0.0))).normalized()
    r = scene.render
    w, h = resolution(scene)
    aspect = (w * r.pixel_aspect_x) / (h * r.pixel_aspect_y)
    fit = cam.data.sensor_fit
    horizontal = fit == "HORIZONTAL" or (fit == "AUTO" and aspect >= 1.0)
    if horizontal:
        fov_y = 2.0 * math.atan(math.tan(cam.data.angle / 2.0) / aspect)
    else:
        fov_y = cam.data.angle
    look_at = position + forward
    return (
        "[camera]\n"
        f"position = {fmt(y_up(position))}\n"
        f"look_at = {fmt(y_up(look_at))}\n"
        f"up = {fmt(y_up(up))}\n"
        f"fov = {math.degrees(fov_y):.9g}\n"
        f"resolution = [{w}, {h}]\n"
    ), (w, h)


def lights_toml(depsgraph, report):

    out = []
    for inst in depsgraph.object_instances:
        obj = inst.object
        if obj.type != "LIGHT":
            continue
        light = obj.data
        m = inst.matrix_world
        pos = m.translation
        axis = (m.to_3x3() @ mathutils.Vector((0.0, 0.0, -1.0))).normalized()
        colour = [c * light.energy for c in light.color]
        if light.type == "POINT":
            out.append(f"[[lights]]\ntype = \"point\"\nposition = {fmt(y_up(pos))}\n"
                       f"power = {fmt(colour)}\n")
        elif light.type == "SPOT":
            half = light.spot_size / 2.0
            intensity = [c / (4.0 * math.pi) for c in colour]
            out.append(
                f"[[lights]]\ntype = \"spot\"\nposition = {fmt(y_up(pos))}\n"
                f"look_at = {fmt(y_up(pos + axis))}\nintensity = {fmt(intensity)}\n"
                f"angle = {math.degrees(half):.9g}\n"
                f"falloff = {math.degrees(half * light.spot_blend):.9g}\n"
            )
        elif light.type == "SUN":
            out.append(f"[[lights]]\ntype = \"directional\"\ndirection = {fmt(y_up(axis))}\n"
                       f"irradiance = {fmt(colour)}\n")
        elif light.type == "AREA":
            sx = light.size * m.to_scale()[0]
            sy = (light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else light.size)
            sy *= m.to_scale()[1]
            if light.shape in ("DISK", "ELLIPSE"):
                if light.shape == "ELLIPSE":
                    report("an elliptic area light is rendered as a disk")
                out.append(
                    f"[[lights]]\ntype = \"disk\"\ncenter = {fmt(y_up(pos))}\n"
                    f"normal = {fmt(y_up(axis))}\nradius = {sx / 2.0:.9g}\n"
                    f"power = {fmt(colour)}\n"
                )
            else:
                r3 = m.to_3x3().normalized()
                ex = r3 @ mathutils.Vector((sx / 2.0, 0.0, 0.0))
                ey = r3 @ mathutils.Vector((0.0, sy / 2.0, 0.0))
                # Counter-clockwise seen from the lit side (−z of the light).
                corners = [pos - ex - ey, pos - ex + ey, pos + ex + ey, pos + ex - ey]
                out.append(
                    "[[lights]]\ntype = \"quad\"\nvertices = ["
                    + ", ".join(fmt(y_up(c)) for c in corners)
                    + f"]\npower = {fmt(colour)}\n"
                )
    return "\n".join(out)


def world_toml(scene, report):
    world = scene.world
    if world is None:
        return ""
    colour, strength = world.color, 1.0
    if world.use_nodes and world.node_tree is not None:
        bg = next((n for n in world.node_tree.nodes if n.type == "BACKGROUND"), None)
        if bg is None:
            report("the world has no Background node: no sky")
            return ""
        if bg.inputs["Color"].is_linked:
            report("a world texture is not mapped: its Background colour is used")
        colour = bg.inputs["Color"].default_value[:3]
        strength = bg.inputs["Strength"].default_value
    radiance = [c * strength for c in colour[:3]]
    if max(radiance) <= 0.0:
        return ""
    return f"[[lights]]\ntype = \"environment\"\nradiance = {fmt(radiance)}\n"


def volume_output(node_tree, kind):
    """The node on the Volume input of the active output node of `kind` ('OUTPUT_MATERIAL' or
    'OUTPUT_WORLD'), and whether its Surface input is linked."""
    if node_tree is None:
        return None, False
    outputs = [n for n in node_tree.nodes if n.type == kind]
    out = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if out is None:
        return None, False
    volume = out.inputs.get("Volume")
    surface = out.inputs.get("Surface")
    node = volume.links[0].from_node if volume is not None and volume.is_linked else None
    return node, surface is not None and surface.is_linked


def medium_of(node, what, report):
    """(σa, σs, g) of a volume shader node (Cycles' coefficients, per metre), or None."""
    def value(socket):
        s = node.inputs[socket]
        if s.is_linked:
            report(f"{what}: the volume's {socket} is driven by nodes, not mapped: its value is used")
        v = s.default_value
        return list(v[:3]) if hasattr(v, "__len__") else v

    zero = [0.0, 0.0, 0.0]
    if node.type == "ADD_SHADER":
        parts = [medium_of(l.from_node, what, report) for i in node.inputs for l in i.links]
        parts = [p for p in parts if p is not None]
        if not parts:
            return None
        sigma_a = [sum(p[0][c] for p in parts) for c in range(3)]
        sigma_s = [sum(p[1][c] for p in parts) for c in range(3)]
        weight = sum(sum(p[1]) for p in parts)
        g = sum(p[2] * sum(p[1]) for p in parts) / weight if weight > 0 else 0.0
        return sigma_a, sigma_s, g
    if node.type == "VOLUME_SCATTER":
        density = max(value("Density"), 0.0)
        return zero, [c * density for c in value("Color")], value("Anisotropy")
    if node.type == "VOLUME_ABSORPTION":
        density = max(value("Density"), 0.0)
        return [(1.0 - c) * density for c in value("Color")], zero, 0.0
    if node.type == "PRINCIPLED_VOLUME":
        density = max(value("Density"), 0.0)
        color = value("Color")
        absorption = value("Absorption Color")
        if value("Emission Strength") > 0.0 or value("Blackbody Intensity") > 0.0:
            report(f"{what}: volume emission is not mapped")
        sigma_a = [max(1.0 - c, 0.0) * max(1.0 - math.sqrt(max(a, 0.0)), 0.0) * density
                   for c, a in zip(color, absorption)]
        return sigma_a, [c * density for c in color], value("Anisotropy")
    report(f"{what}: a {node.bl_label} volume is not mapped")
    return None


def medium_toml(name, medium):
    sigma_a, sigma_s, g = medium
    g = min(max(g, -0.99), 0.99)
    return (f"[media.{toml_string(name)}]\nsigma_a = {fmt(sigma_a)}\nsigma_s = {fmt(sigma_s)}\n"
            f"g = {float(g):.9g}\n")


def write_ply(path, obj, depsgraph):
    """The evaluated mesh of `obj` in world space (y-up, as the glTF export), as ASCII PLY."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        m = obj.matrix_world
        vertices = [y_up(m @ v.co) for v in mesh.vertices]
        triangles = [tuple(t.vertices) for t in mesh.loop_triangles]
    finally:
        evaluated.to_mesh_clear()
    with open(path, "w", encoding="ascii") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n")
        f.write(f"element face {len(triangles)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in vertices:
            f.write(f"{v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
        for t in triangles:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")


def grid_volumes(depsgraph, directory, report):
    """Volume objects (OpenVDB grids, such as a baked smoke) with a volume material: each as a
    grid medium (its .vdb copied beside the scene) inside an invisible box around the object's
    bounds. As in Cycles, the material's density multiplies the grid named by its Density
    Attribute, and the grids sit in the object's space."""
    parts = []
    objects = {i.object.original for i in depsgraph.object_instances if i.object.type == "VOLUME"}
    for k, obj in enumerate(sorted(objects, key=lambda o: o.name)):
        what = f"volume object '{obj.name}'"
        mat = obj.active_material
        node = volume_output(mat.node_tree, "OUTPUT_MATERIAL")[0] if mat and mat.use_nodes else None
        medium = medium_of(node, what, report) if node is not None else None
        if medium is None:
            report(f"{what}: no volume material, not mapped")
            continue
        volume = obj.data
        volume.grids.load()
        source = bpy.path.abspath(volume.grids.frame_filepath or volume.filepath)
        if not os.path.isfile(source):
            report(f"{what}: its file '{source}' is not there, not mapped")
            continue
        grid_file = f"volume{k}.vdb"
        shutil.copyfile(source, os.path.join(directory, grid_file))
        attribute = node.inputs.get("Density Attribute") if node.type == "PRINCIPLED_VOLUME" else None
        grid_name = (attribute.default_value if attribute is not None else "") or "density"
        m = obj.matrix_world
        rows = [[m[r][c] for c in range(4)] for r in (0, 2, 1)]
        rows[2] = [-x for x in rows[2]]  # y-up: (x, y, z) -> (x, z, -y)
        matrix = ", ".join(fmt(r) for r in rows + [[0.0, 0.0, 0.0, 1.0]])
        name = f"{obj.name} grid"
        parts.append(medium_toml(name, medium)
                     + f"grid = \"{grid_file}\"\ngrid_name = {toml_string(grid_name)}\n"
                     + f"transform = {{ matrix = [{matrix}] }}\n")
        corners = [y_up(m @ mathutils.Vector(c)) for c in obj.evaluated_get(depsgraph).bound_box]
        low = [min(c[a] for c in corners) for a in range(3)]
        high = [max(c[a] for c in corners) for a in range(3)]
        pad = 1e-4 * max(h - l for l, h in zip(low, high))
        parts.append(f"[[shapes]]\ntype = \"box\"\nmin = {fmt([l - pad for l in low])}\n"
                     f"max = {fmt([h + pad for h in high])}\ninterior = {toml_string(name)}\n")
    return parts


def volume_objects(depsgraph, report):
    """Mesh objects whose material has a volume and no surface: (object, material name,
    medium)."""
    out = []
    for obj in {i.object.original for i in depsgraph.object_instances if i.object.type == "MESH"}:
        for slot in obj.material_slots:
            mat = slot.material
            if mat is None or not mat.use_nodes:
                continue
            node, has_surface = volume_output(mat.node_tree, "OUTPUT_MATERIAL")
            if node is None:
                continue
            what = f"material '{mat.name}'"
            if has_surface:
                report(f"{what}: a volume inside a surface is not mapped (the surface is)")
                continue
            medium = medium_of(node, what, report)
            if medium is not None:
                out.append((obj, mat.name, medium))
                break
    out.sort(key=lambda o: o[0].name)
    return out


def unique_media(volumes):
    """Each material's medium once (objects may share a material), in object order."""
    seen = {}
    for _, name, medium in volumes:
        seen.setdefault(name, medium)
    return list(seen.items())


# The glTF add-on's settings group, by the names its exporter looks for (a prefix, any case).
GLTF_SETTINGS_GROUPS = ("gltf material output", "gltf settings")


def gltf_dispersion(mat, report):
    """The Dispersion input (20 / V_d) of the glTF Material Output group in `mat`'s node tree,
    or 0 where it has none."""
    if mat is None or mat.node_tree is None:
        return 0.0
    for node in mat.node_tree.nodes:
        tree = getattr(node, "node_tree", None)
        if node.type != "GROUP" or tree is None or not tree.name.lower().startswith(
                GLTF_SETTINGS_GROUPS):
            continue
        socket = node.inputs.get("Dispersion")
        if socket is None:
            continue
        if socket.is_linked:
            report(f"material '{mat.name}': its Dispersion is driven by nodes, not mapped: its "
                   "value is used")
        return max(float(socket.default_value), 0.0)
    return 0.0


def add_dispersion(glb, report):
    """Give the exported materials of the GLB file `glb` (by name, as the exporter names them)
    the KHR_materials_dispersion of their glTF Material Output group, where the exporter wrote
    none (before Blender's newer exporters, or there without KHR_materials_volume)."""
    if not any(gltf_dispersion(m, lambda _: None) for m in bpy.data.materials):
        return
    with open(glb, "rb") as f:
        data = f.read()
    # GLB: a 12-byte header, then the JSON chunk (length, type, text), then the BIN chunk.
    json_length, chunk_type = struct.unpack_from("<I4s", data, 12)
    if data[:4] != b"glTF" or chunk_type != b"JSON":
        raise RuntimeError(f"{glb} is not the GLB file Blender's exporter writes")
    doc = json.loads(data[20:20 + json_length])
    changed = False
    for material in doc.get("materials", []):
        value = gltf_dispersion(bpy.data.materials.get(material.get("name", "")), report)
        extensions = material.get("extensions", {})
        if value and "KHR_materials_dispersion" not in extensions:
            extensions["KHR_materials_dispersion"] = {"dispersion": value}
            material["extensions"] = extensions
            changed = True
    if not changed:
        return
    used = doc.setdefault("extensionsUsed", [])
    if "KHR_materials_dispersion" not in used:
        used.append("KHR_materials_dispersion")
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)  # chunks are 4-byte aligned; JSON pads with spaces
    rest = data[20 + json_length:]
    with open(glb, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 20 + len(text) + len(rest)))
        f.write(struct.pack("<I4s", len(text), b"JSON") + text + rest)


def export_scene(depsgraph, directory, report=lambda m: None):
    """Write the Photon scene of the evaluated `depsgraph` into `directory`; returns the
    .toml path and the resolution."""
    scene = depsgraph.scene
    glb = os.path.join(directory, "meshes.glb")
    volumes = volume_objects(depsgraph, report)
    bounding = {o.name for o, _, _ in volumes}
    meshes = [i.object.original for i in depsgraph.object_instances if i.object.type == "MESH"]
    has_meshes = any(o.name not in bounding for o in meshes)
    if has_meshes:
        # The boundaries of media are written apart; the glTF holds every other mesh.
        hidden = [o for o in meshes if o.name in bounding and not o.hide_get()]
        for o in hidden:
            o.hide_set(True)
        try:
            bpy.ops.export_scene.gltf(
                filepath=glb,
                export_format="GLB",
                export_apply=True,
                export_cameras=False,
                export_lights=False,
                export_yup=True,
                use_visible=True,
            )
        finally:
            for o in hidden:
                o.hide_set(False)
        add_dispersion(glb, report)
    camera, size = camera_toml(scene)
    world_volume, _ = volume_output(
        scene.world.node_tree if scene.world is not None and scene.world.use_nodes else None,
        "OUTPUT_WORLD",
    )
    atmosphere = medium_of(world_volume, "the world", report) if world_volume else None
    parts = [f"name = {toml_string(scene.name)}\n"]
    if atmosphere is not None:
        parts[0] += 'medium = "world"\n'
    parts.append(camera)
    if atmosphere is not None:
        parts.append(medium_toml("world", atmosphere))
    for name, medium in unique_media(volumes):
        parts.append(medium_toml(name, medium))
    if has_meshes:
        parts.append("[[shapes]]\ntype = \"mesh\"\nfile = \"meshes.glb\"\n")
    parts.extend(grid_volumes(depsgraph, directory, report))
    for k, (obj, name, medium) in enumerate(volumes):
        ply = f"volume{k}.ply"
        write_ply(os.path.join(directory, ply), obj, depsgraph)
        parts.append(f"[[shapes]]\ntype = \"mesh\"\nfile = \"{ply}\"\nsmooth = false\n"
                     f"interior = {toml_string(name)}\n")
    parts.append(lights_toml(depsgraph, report))
    parts.append(world_toml(scene, report))
    path = os.path.join(directory, "scene.toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(p for p in parts if p))
    return path, size


def options(settings):
    """The panel's render settings for the chosen integrator (Photon refuses a setting the
    integrator does not take); 0 leaves spp and max_depth to the integrator's default."""
    o = {"integrator": settings.integrator, "seed": settings.seed}
    if settings.spectral:
        o["spectral"] = True
    if settings.max_depth:
        o["max_depth"] = settings.max_depth
    if settings.integrator in PHOTON_PASSES:
        o.update(passes=settings.passes, photons_per_pass=settings.photons_per_pass)
    elif settings.integrator in PROGRESSIVE:
        o["passes"] = settings.passes
    else:
        if settings.spp:
            o["spp"] = settings.spp
        if settings.integrator == "photon":
            o["photons"] = settings.photons
    return o


class PhotonRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PHOTON"
    bl_label = "Photon"
    bl_use_preview = False

    def render(self, depsgraph):
        # An exception leaving a render engine leaves Blender without a result: writing the
        # image then crashed it (EXR) or wrote nothing without a word (PNG). Every error is
        # reported instead, over an empty image when no pass was shown.
        shown = []
        try:
            self.render_photon(depsgraph, shown)
        except Exception as e:  # noqa: BLE001 - any error, Photon's or the export's
            self.report({"ERROR"}, f"Photon: {e}")
            if not shown:
                w, h = resolution(depsgraph.scene)
                self.show(np_zeros_rgba(w, h), w, h)

    def show(self, rgba, w, h):
        result = self.begin_result(0, 0, w, h)
        result.layers[0].passes["Combined"].rect = rgba.reshape(-1, 4)
        self.end_result(result)

    def render_photon(self, depsgraph, shown):
        import numpy as np
        import photon_render

        settings = depsgraph.scene.photon
        with tempfile.TemporaryDirectory(prefix="photon-blender-") as tmp:
            path, (w, h) = export_scene(
                depsgraph, tmp, lambda m: self.report({"WARNING"}, m)
            )
            scene = photon_render.load_scene(path)
            for warning in scene.warnings:
                self.report({"WARNING"}, warning)
        o = options(settings)
        threads = settings.threads or None

        def show(image):
            # Blender's rows run bottom to top, as RGBA.
            rgba = np.ones((h, w, 4), dtype=np.float32)
            rgba[:, :, :3] = image[::-1]
            self.show(rgba, w, h)
            shown.append(True)

        if settings.integrator in PROGRESSIVE:
            image = None
            for i, image in enumerate(photon_render.progressive(scene, threads=threads, **o)):
                self.update_progress((i + 1) / settings.passes)
                self.update_stats("", f"Photon: pass {i + 1}/{settings.passes}")
                if self.test_break():
                    break
                if (i + 1) & i == 0 or i + 1 == settings.passes:
                    show(image)
            if image is not None:
                show(image)
        else:
            self.update_stats("", "Photon: rendering")
            image, _ = photon_render.render(scene, threads=threads, **o)
            show(image)


def np_zeros_rgba(w, h):
    import numpy as np

    return np.zeros((h, w, 4), dtype=np.float32)


class RENDER_PT_photon(bpy.types.Panel):
    bl_label = "Photon"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"PHOTON"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        s = context.scene.photon
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "integrator")
        if s.integrator in PROGRESSIVE:
            layout.prop(s, "passes")
            if s.integrator in PHOTON_PASSES:
                layout.prop(s, "photons_per_pass")
        else:
            layout.prop(s, "spp")
            if s.integrator == "photon":
                layout.prop(s, "photons")
        layout.prop(s, "max_depth")
        layout.prop(s, "spectral")
        layout.prop(s, "seed")
        layout.prop(s, "threads")


CLASSES = (PhotonRenderSettings, PhotonRenderEngine, RENDER_PT_photon)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)
    bpy.types.Scene.photon = bpy.props.PointerProperty(type=PhotonRenderSettings)


def unregister():
    del bpy.types.Scene.photon
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
