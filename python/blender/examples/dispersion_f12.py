"""Dispersion in Blender, rendered with F12 through the Photon add-on.

Usage (Blender as a Python module, `pip install bpy`, with `photon_render` installed)::

    python python/blender/examples/dispersion_f12.py OUT.png [--seconds N] [--rgb]
        [--passes N] [--photons-per-pass N] [--width W] [--height H]

What it builds, in bpy, from an empty scene:

- a triangular glass prism (equilateral, 60° apex, standing on its base) whose material is a
  Principled BSDF with Transmission 1, Roughness 0 and IOR 1.7, and a glTF Material Output
  node group (the glTF exporter's settings group) whose Dispersion is 1.5, glTF's 20 / V_d:
  an Abbe number of 13.3, more dispersive than any flint glass (the densest are near 17;
  rutile is near 10), so the spectrum is wide. Blender has no dispersion of its own; the
  add-on reads this input and gives the glass to Photon as KHR_materials_dispersion;
- a white diffuse floor and back wall (2.8 m behind the prism);
- a spot light with a narrow cone (0.6° half-angle) aimed at the prism's near face at the
  angle of minimum deviation (for the index at the d line), tilted 5° upwards, so the beam
  leaves through the other face towards the wall, where it lands as a caustic: a spectrum
  about 35 cm wide (red bent least, violet most) when rendered spectrally, a round white
  spot in RGB (which uses the index at the d line for every colour);
- a dim square area light above (the room's light) and a camera looking over the prism at
  the wall.

Then it sets the add-on's settings (integrator "sppm", Spectral on unless --rgb, passes and
photons per pass), renders with F12's operator (`bpy.ops.render.render(write_still=True)`,
render engine "PHOTON") and writes OUT.png (view transform Standard, so the spectrum's
colours are not desaturated).

How long it takes: about --seconds (default 75) in all, plus about 5 s to import bpy and
build the scene. The add-on's budget is a number of passes, so the script first times a short
run of the exported scene (a tenth of the budget, at least 4 s) and gives F12 the passes that
fill the rest; --passes N skips that. On 2 cores at the default 480 × 320 that was about 990
passes of 25 000 photons in 67 s of F12 (spectral; about 1140 in RGB), 75 s in all. Many
passes with few photons each: all the photons and camera paths of one pass share its three
wavelengths (only the hero one after the prism), so the spectrum is sampled once per pass.
The picture: docs/images/blender-dispersion.png.
"""

import argparse
import math
import os
import sys
import tempfile
import time

import bpy
import mathutils

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # python/blender, the add-on's folder
import photon_blender  # noqa: E402

IOR = 1.7  # index at the d line (587.6 nm)
DISPERSION = 1.5  # glTF's 20 / V_d: V_d = 13.3
SIDE = 0.2  # prism's side (m)
HEIGHT = 0.22  # prism's height (m)
LIFT = 0.001  # gap under the prism (m)
BEAM_Z = 0.11  # height of the beam where it enters the prism
BEAM_TILT = 5.0  # degrees upwards, so that the spectrum lands higher on the wall
SPOT_DISTANCE = 0.6  # spot light to the prism's face
SPOT_HALF_ANGLE = 0.6  # degrees
SPOT_POWER = 4000.0  # W (Blender's spot power: intensity P / 4π W/sr)
WALL_Y = 2.8
ROOM_LIGHT = 14.0  # W, the area light above


def principled(name, base, roughness, **inputs):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    for socket, value in inputs.items():
        bsdf.inputs[socket].default_value = value
    return mat


def gltf_settings_group():
    """The glTF exporter's "glTF Material Output" node group (Add > Output in the shader
    editor, where the glTF add-on is enabled), with its Dispersion input."""
    group = bpy.data.node_groups.get("glTF Material Output")
    if group is None:
        group = bpy.data.node_groups.new("glTF Material Output", "ShaderNodeTree")
        for name in ("Occlusion", "Thickness", "Dispersion"):
            group.interface.new_socket(name, socket_type="NodeSocketFloat")
    return group


def rot(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return mathutils.Vector((c * v.x - s * v.y, s * v.x + c * v.y))


def cross2(a, b):
    return a.x * b.y - a.y * b.x


def prism_layout():
    """The prism's corners (2D, on the floor) and the beam: the spot's position and aim, for
    a beam that leaves towards +y after crossing the prism parallel to its base (minimum
    deviation at the d line)."""
    apex_angle = math.radians(60.0)
    deviation = 2.0 * math.asin(IOR * math.sin(apex_angle / 2.0)) - apex_angle
    out = mathutils.Vector((0.0, 1.0))
    incoming = rot(out, -deviation)
    along_base = rot(out, -deviation / 2.0)
    right = mathutils.Vector((along_base.y, -along_base.x))  # towards the apex
    radius = SIDE / math.sqrt(3.0)
    apex = right * radius
    corners = [apex, rot(apex, 2.0 * math.pi / 3.0), rot(apex, -2.0 * math.pi / 3.0)]
    # Inside, the beam runs parallel to the base, 40% of the way from the apex to the base.
    inside = apex - right * (0.4 * 1.5 * radius)
    hits = []
    for corner in corners[1:]:
        edge = corner - apex
        # inside + t·along_base = apex + u·edge
        den = cross2(along_base, edge)
        t = cross2(apex - inside, edge) / den
        hits.append(inside + along_base * t)
    entry = min(hits, key=lambda p: p.dot(along_base))
    return corners, entry, incoming


def prism_object(corners, mat):
    # 1 mm above the floor: a face on the floor's plane would make the two hard to tell apart.
    verts = [(c.x, c.y, LIFT) for c in corners] + [(c.x, c.y, LIFT + HEIGHT) for c in corners]
    # Counter-clockwise corners (seen from above): outward normals.
    if cross2(corners[1] - corners[0], corners[2] - corners[0]) < 0:
        verts = [verts[0], verts[2], verts[1], verts[3], verts[5], verts[4]]
    faces = [(0, 2, 1), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)]
    mesh = bpy.data.meshes.new("prism")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new("prism", mesh)
    bpy.context.scene.collection.objects.link(obj)
    mesh.materials.append(mat)
    return obj


def plane(name, location, rotation, size, mat):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location, rotation=rotation)
    obj = bpy.context.active_object
    obj.name = name
    obj.data.materials.append(mat)
    return obj


def aim(obj, target):
    direction = mathutils.Vector(target) - obj.location
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def build_scene(width, height):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100

    white = principled("white", (0.8, 0.8, 0.8), roughness=1.0)
    plane("floor", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 8.0, white)
    plane("wall", (0.0, WALL_Y, 1.5), (math.pi / 2, 0.0, 0.0), 8.0, white)

    glass = principled("flint", (1.0, 1.0, 1.0), roughness=0.0,
                       **{"Transmission Weight": 1.0, "IOR": IOR})
    settings = glass.node_tree.nodes.new("ShaderNodeGroup")
    settings.node_tree = gltf_settings_group()
    settings.inputs["Dispersion"].default_value = DISPERSION
    corners, entry, incoming = prism_layout()
    prism_object(corners, glass)

    target = mathutils.Vector((entry.x, entry.y, BEAM_Z))
    slope = math.tan(math.radians(BEAM_TILT))
    position = target - mathutils.Vector((incoming.x, incoming.y, slope)) * SPOT_DISTANCE
    bpy.ops.object.light_add(type="SPOT", location=position)
    spot = bpy.context.active_object
    aim(spot, target)
    spot.data.energy = SPOT_POWER
    spot.data.spot_size = math.radians(2.0 * SPOT_HALF_ANGLE)
    spot.data.spot_blend = 0.3
    spot.data.shadow_soft_size = 0.0

    bpy.ops.object.light_add(type="AREA", location=(0.0, -0.3, 2.6))
    room = bpy.context.active_object.data
    room.shape, room.size, room.energy = "SQUARE", 1.5, ROOM_LIGHT

    bpy.ops.object.camera_add(location=(-0.8, -1.8, 0.3))
    camera = bpy.context.active_object
    aim(camera, (-0.05, 1.4, 0.2))
    camera.data.angle = math.radians(34.0)
    scene.camera = camera
    return scene


def use_photon(scene, spectral, passes, photons):
    scene.render.engine = "PHOTON"
    s = scene.photon
    s.integrator = "sppm"
    s.spectral = spectral
    s.passes = passes
    s.photons_per_pass = photons
    s.threads = 0
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.color_depth = "8"
    scene.render.image_settings.compression = 100


def passes_for(scene, seconds, spectral, photons):
    """How many passes fill `seconds`: a short run of the exported scene, timed."""
    import photon_render

    trial = max(4.0, 0.1 * seconds)
    with tempfile.TemporaryDirectory(prefix="photon-dispersion-") as tmp:
        path, _ = photon_blender.export_scene(bpy.context.evaluated_depsgraph_get(), tmp)
        loaded = photon_render.load_scene(path)
    options = dict(integrator="sppm", photons_per_pass=photons, time=trial)
    if spectral:
        options["spectral"] = True
    start = time.monotonic()
    done = sum(1 for _ in photon_render.progressive(loaded, **options))
    per_pass = (time.monotonic() - start) / max(done, 1)
    return max(1, int((seconds - trial) / per_pass)), per_pass


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="the PNG to write")
    parser.add_argument("--seconds", type=float, default=75.0,
                        help="render time budget, the timing run included (default 75)")
    parser.add_argument("--passes", type=int, default=0, help="passes (skips the timing run)")
    parser.add_argument("--photons-per-pass", type=int, default=25_000)
    parser.add_argument("--rgb", action="store_true", help="Spectral off (no dispersion)")
    parser.add_argument("--width", type=int, default=480)
    parser.add_argument("--height", type=int, default=320)
    args = parser.parse_args()

    scene = build_scene(args.width, args.height)
    photon_blender.register()
    try:
        spectral = not args.rgb
        passes = args.passes
        if not passes:
            passes, per_pass = passes_for(scene, args.seconds, spectral, args.photons_per_pass)
            print(f"timing run: {per_pass:.3f} s a pass → {passes} passes")
        use_photon(scene, spectral, passes, args.photons_per_pass)
        scene.render.filepath = os.path.abspath(args.out)
        start = time.monotonic()
        bpy.ops.render.render(write_still=True)
        print(f"F12: {passes} passes of {args.photons_per_pass} photons, "
              f"{'spectral' if spectral else 'RGB'}, {args.width}×{args.height}, "
              f"{time.monotonic() - start:.1f} s → {args.out}")
    finally:
        # With the add-on still registered, bpy (4.5) hangs at exit.
        photon_blender.unregister()


if __name__ == "__main__":
    main()
