"""The Blender add-on, headless (Blender as a Python module, `pip install bpy`): the seed's
Cornell box built in Python, rendered with the Photon engine (F12's path: bpy.ops.render),
against `photon render` of the same scene exported to glTF by Blender. Skipped where bpy is
not installed."""

import json
import math
import os
import re
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
import mathutils  # noqa: E402

from test_photon import photon_cli, read_pfm  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python" / "blender"))
import photon_blender  # noqa: E402

SIZE = 64
PASSES = 24
PHOTONS = 100_000


def principled(name, base, metallic=0.0, roughness=0.5, **inputs):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    for socket, value in inputs.items():
        bsdf.inputs[socket].default_value = value
    return mat


def plane(name, location, rotation, size, mat):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location, rotation=rotation)
    obj = bpy.context.active_object
    obj.name = name
    obj.data.materials.append(mat)
    return obj


def cornell_box():
    """The seed's box: 2 m, red left, green right, white elsewhere, a mirror sphere and a
    glass sphere, an emissive disk under the ceiling and a small point light."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = SIZE
    scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    white = principled("white", (0.75, 0.75, 0.75), roughness=1.0)
    red = principled("red", (0.75, 0.1, 0.1), roughness=1.0)
    green = principled("green", (0.1, 0.6, 0.1), roughness=1.0)
    plane("floor", (0, 0, 0), (0, 0, 0), 2, white)
    plane("ceiling", (0, 0, 2), (math.pi, 0, 0), 2, white)
    plane("back", (0, 1, 1), (math.pi / 2, 0, 0), 2, white)
    plane("left", (-1, 0, 1), (0, math.pi / 2, 0), 2, red)
    plane("right", (1, 0, 1), (0, -math.pi / 2, 0), 2, green)
    mirror = principled("mirror", (0.95, 0.95, 0.95), metallic=1.0, roughness=0.0)
    glass = principled(
        "glass", (1, 1, 1), roughness=0.0, **{"Transmission Weight": 1.0, "IOR": 1.5}
    )
    for name, loc, mat in [("mirror", (-0.45, 0.3, 0.4), mirror), ("glass", (0.45, -0.2, 0.4), glass)]:
        bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.4, location=loc)
        obj = bpy.context.active_object
        obj.name = name
        bpy.ops.object.shade_smooth()
        obj.data.materials.append(mat)
    lamp = principled(
        "lamp", (0, 0, 0), **{"Emission Color": (1, 1, 1, 1), "Emission Strength": 30.0}
    )
    bpy.ops.mesh.primitive_circle_add(
        vertices=32, radius=0.3, fill_type="NGON", location=(0, 0, 1.99), rotation=(math.pi, 0, 0)
    )
    bpy.context.active_object.data.materials.append(lamp)
    bpy.ops.object.light_add(type="POINT", location=(0.5, -0.6, 1.6))
    bpy.context.active_object.data.energy = 20.0
    bpy.ops.object.camera_add(location=(0, -3.9, 1), rotation=(math.pi / 2, 0, 0))
    scene.camera = bpy.context.active_object
    scene.camera.data.angle = math.radians(40)
    return scene


def use_photon(scene, passes=PASSES, integrator="sppm"):
    """Render `scene` with the Photon engine (sppm unless told) to linear 32-bit EXR."""
    scene.render.engine = "PHOTON"
    s = scene.photon
    s.integrator, s.passes, s.photons_per_pass = integrator, passes, PHOTONS
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"


def render_both(scene, tmp_path, passes=PASSES, integrator="sppm"):
    """The scene through the Photon engine (F12's path) and through `photon render` of
    Blender's glTF export of it; returns the two EXR paths."""
    use_photon(scene, passes, integrator)
    engine_out = tmp_path / "engine.exr"
    scene.render.filepath = str(engine_out)
    bpy.ops.render.render(write_still=True)
    assert engine_out.exists()
    glb = tmp_path / "scene.glb"
    bpy.ops.export_scene.gltf(
        filepath=str(glb), export_format="GLB", export_apply=True,
        export_cameras=True, export_lights=True,
    )
    cli_out = tmp_path / "cli.exr"
    photons = ["--photons-per-pass", str(PHOTONS)] if integrator in ("sppm", "ppm") else []
    subprocess.run(
        [photon_cli(), "render", str(glb), "--integrator", integrator, "--passes", str(passes),
         *photons, "--width", str(SIZE), "--height", str(SIZE), "-q", "-o", str(cli_out)],
        check=True,
    )
    return engine_out, cli_out


def compare(a, b):
    """relMSE and mean ratios (a / b) from `photon compare`."""
    out = subprocess.run(
        [photon_cli(), "compare", str(a), str(b)], check=True, capture_output=True, text=True
    ).stdout
    overall = next(l for l in out.splitlines() if l.startswith("overall")).split()
    return out, float(overall[2]), float(overall[3])


def assert_both_routes_agree(build, tmp_path, integrator="sppm", passes=PASSES):
    """Build a scene with the add-on registered, render it through the engine and through
    Blender's glTF export and the CLI: the same scene by two routes (the add-on's own camera
    and light mapping; Blender's export of them), equal within the noise of the passes."""
    photon_blender.register()
    try:
        engine_out, cli_out = render_both(build(), tmp_path, passes, integrator)
    finally:
        photon_blender.unregister()
    table, rel_mse, mean_ratio = compare(engine_out, cli_out)
    print(table)
    assert abs(mean_ratio - 1.0) < 0.03, table
    assert rel_mse < 0.02, table


def test_the_photon_engine_renders_the_cornell_box_like_the_cli_renders_its_gltf(tmp_path):
    assert_both_routes_agree(cornell_box, tmp_path)


def test_the_engine_renders_with_vertex_connection_and_merging_like_the_cli(tmp_path):
    # The Integrator menu's VCM: passes without photons per pass (one light path a pixel).
    assert_both_routes_agree(cornell_box, tmp_path, integrator="vcm", passes=64)
    s = types.SimpleNamespace(integrator="vcm", seed=0, max_depth=0, spp=0, spectral=False,
                              passes=16, photons_per_pass=PHOTONS)
    assert photon_blender.options(s) == {"integrator": "vcm", "seed": 0, "passes": 16}


def test_spot_and_sun_lights_map_as_blenders_gltf_export_does(tmp_path):
    def spot_and_sun():
        scene = cornell_box()
        # Only a spot light inside and the sun through the open front: no disk, no point.
        for obj in list(scene.objects):
            if obj.type == "LIGHT" or obj.name.startswith("Circle"):
                bpy.data.objects.remove(obj)
        bpy.ops.object.light_add(type="SPOT", location=(0.3, -0.5, 1.8), rotation=(0.3, 0.2, 0))
        spot = bpy.context.active_object.data
        spot.energy, spot.spot_size, spot.spot_blend = 60.0, math.radians(70), 0.15
        bpy.ops.object.light_add(type="SUN", rotation=(math.radians(70), 0, math.radians(15)))
        bpy.context.active_object.data.energy = 2.0
        return scene

    assert_both_routes_agree(spot_and_sun, tmp_path)


def test_an_area_light_emits_what_an_emissive_surface_of_its_radiance_does(tmp_path):
    """A square area light of power P and side s is a one-sided Lambertian emitter of
    radiance P / (π s²): the same image as an emissive, one-sided square of that radiance
    (glTF emissive strength is radiance in Photon's importer)."""
    power, side = 40.0, 0.5

    def box_with(light):
        scene = cornell_box()
        for obj in list(scene.objects):
            if obj.type == "LIGHT" or obj.name.startswith("Circle"):
                bpy.data.objects.remove(obj)
        light(scene)
        use_photon(scene)
        return scene

    def area(scene):
        bpy.ops.object.light_add(type="AREA", location=(0.2, 0.1, 1.9))
        light = bpy.context.active_object.data
        light.shape, light.size, light.energy = "SQUARE", side, power

    def emissive(scene):
        radiance = power / (math.pi * side * side)
        mat = principled(
            "panel", (0, 0, 0), **{"Emission Color": (1, 1, 1, 1), "Emission Strength": radiance}
        )
        mat.use_backface_culling = True  # one-sided, as the area light is
        # Facing down, as the light does (a plane's normal is +z; turn it over).
        plane("panel", (0.2, 0.1, 1.9), (math.pi, 0, 0), side, mat)

    photon_blender.register()
    try:
        outs = []
        for name, light in [("area", area), ("emissive", emissive)]:
            scene = box_with(light)
            out = tmp_path / f"{name}.exr"
            scene.render.filepath = str(out)
            bpy.ops.render.render(write_still=True)
            outs.append(out)
    finally:
        photon_blender.unregister()
    table, rel_mse, mean_ratio = compare(*outs)
    print(table)
    assert abs(mean_ratio - 1.0) < 0.03, table
    assert rel_mse < 0.05, table


# A small scene rendered by the engine in a process of its own (a crash must fail the test,
# not end the test run): argv = add-on folder, file format, width, output, scene name.
ENGINE_RUN = """
import os, sys
import bpy
sys.path.insert(0, sys.argv[1])
import photon_blender
file_format, width, out, name = sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.name = name
scene.render.resolution_x, scene.render.resolution_y = width, 8
scene.render.resolution_percentage = 100
bpy.ops.mesh.primitive_plane_add(size=2)
bpy.ops.object.light_add(type="POINT", location=(0, 0, 2))
bpy.ops.object.camera_add(location=(0, 0, 3))
scene.camera = bpy.context.active_object
photon_blender.register()
scene.render.engine = "PHOTON"
scene.photon.integrator, scene.photon.passes, scene.photon.photons_per_pass = "sppm", 2, 1000
scene.render.image_settings.file_format = file_format
scene.render.filepath = out
try:
    print("RESULT", bpy.ops.render.render(write_still=True), flush=True)
except RuntimeError as e:
    print("RAISED", e, flush=True)
# bpy's own teardown can hang at exit; the render is over.
os._exit(0)
"""


def engine_run(tmp_path, file_format, width, name="Scene"):
    script = tmp_path / "engine_run.py"
    script.write_text(ENGINE_RUN)
    return subprocess.run(
        [sys.executable, str(script), str(ROOT / "python" / "blender"), file_format, str(width),
         str(tmp_path / "out"), name],
        capture_output=True, text=True, timeout=600,
    )


@pytest.mark.parametrize("file_format", ["OPEN_EXR", "PNG"])
def test_a_photon_error_is_reported_not_a_crash(tmp_path, file_format):
    # 40000 pixels wide: more than Photon renders, so it raises PhotonError.
    out = engine_run(tmp_path, file_format, 40000)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "RAISED" in out.stdout, out.stdout + out.stderr[-3000:]
    assert "Photon:" in out.stdout and "32768" in out.stdout, out.stdout


def test_the_scene_name_is_escaped_in_the_toml(tmp_path):
    import tomllib

    name = 'a "b" \\ c\nname = "x"\t\u2603'
    out = engine_run(tmp_path, "PNG", 16, name)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "RESULT {'FINISHED'}" in out.stdout, out.stdout + out.stderr[-3000:]
    scene = cornell_box()
    scene.name = name
    depsgraph = bpy.context.evaluated_depsgraph_get()
    path, _ = photon_blender.export_scene(depsgraph, str(tmp_path))
    with open(path, "rb") as f:
        assert tomllib.load(f)["name"] == scene.name


def floor_stage():
    """An empty scene of SIZE² pixels with a grey floor."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = SIZE
    scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    plane("floor", (0, 0, 0), (0, 0, 0), 6, principled("floor", (0.6, 0.6, 0.6), roughness=1.0))
    return scene


def principled_volume(name, **inputs):
    """A material with a Principled Volume (these inputs set) on its Volume output and nothing
    on its Surface."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    volume = nodes.new("ShaderNodeVolumePrincipled")
    for socket, value in inputs.items():
        volume.inputs[socket].default_value = value
    mat.node_tree.links.new(volume.outputs["Volume"], nodes["Material Output"].inputs["Volume"])
    return mat


def fog_stage():
    """A floor in thin fog (a Volume Scatter on the World) under a spot light, with a cube of
    smoke (a Principled Volume, no surface) on it."""
    scene = floor_stage()
    smoke = principled_volume("smoke", Color=(0.8, 0.7, 0.6, 1.0), Density=2.0, Anisotropy=0.3,
                              **{"Absorption Color": (0.25, 0.36, 0.81, 1.0)})
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.4, 0, 0.5))
    bpy.context.active_object.name = "smoke"
    bpy.context.active_object.data.materials.append(smoke)
    world = bpy.data.worlds.new("world")
    scene.world = world
    world.use_nodes = True
    wnodes = world.node_tree.nodes
    wnodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    scatter = wnodes.new("ShaderNodeVolumeScatter")
    scatter.inputs["Color"].default_value = (0.9, 0.9, 0.9, 1.0)
    scatter.inputs["Density"].default_value = 0.1
    scatter.inputs["Anisotropy"].default_value = 0.2
    world.node_tree.links.new(scatter.outputs["Volume"], wnodes["World Output"].inputs["Volume"])
    bpy.ops.object.light_add(type="SPOT", location=(0, 0, 3), rotation=(0, 0, 0))
    spot = bpy.context.active_object.data
    spot.energy, spot.spot_size, spot.spot_blend = 300.0, math.radians(50), 0.0
    bpy.ops.object.camera_add(location=(0, -4.5, 1.2), rotation=(math.radians(80), 0, 0))
    scene.camera = bpy.context.active_object
    scene.camera.data.angle = math.radians(45)
    return scene


def test_fog_and_smoke_map_to_cycles_coefficients_and_render_by_f12_as_by_the_cli(tmp_path):
    import tomllib

    scene = fog_stage()
    reports = []
    depsgraph = bpy.context.evaluated_depsgraph_get()
    path, _ = photon_blender.export_scene(depsgraph, str(tmp_path), reports.append)
    with open(path, "rb") as f:
        toml = tomllib.load(f)
    assert reports == [], reports
    # Cycles: Volume Scatter σs = colour · density; Principled Volume σs = colour · density,
    # σa = (1 − colour)(1 − √absorption colour) · density.
    assert toml["medium"] == "world"
    world = toml["media"]["world"]
    assert world["sigma_s"] == pytest.approx([0.09] * 3)
    assert world["sigma_a"] == [0.0] * 3
    assert world["g"] == pytest.approx(0.2)
    smoke = toml["media"]["smoke"]
    assert smoke["sigma_s"] == pytest.approx([1.6, 1.4, 1.2])
    assert smoke["sigma_a"] == pytest.approx(
        [0.2 * 0.5 * 2.0, 0.3 * 0.4 * 2.0, 0.4 * 0.1 * 2.0], rel=1e-5
    )
    assert smoke["g"] == pytest.approx(0.3)
    boundary = [s for s in toml["shapes"] if s.get("interior") == "smoke"]
    assert len(boundary) == 1 and "material" not in boundary[0]
    ply = (tmp_path / boundary[0]["file"]).read_text()
    assert "element face 12" in ply  # the cube, triangulated
    # F12 (the engine, through the Python module) against `photon render` of the export.
    photon_blender.register()
    try:
        use_photon(scene, passes=8)
        engine_out = tmp_path / "engine.exr"
        scene.render.filepath = str(engine_out)
        bpy.ops.render.render(write_still=True)
    finally:
        photon_blender.unregister()
    cli_out = tmp_path / "cli.exr"
    subprocess.run(
        [photon_cli(), "render", path, "--integrator", "sppm", "--passes", "8",
         "--photons-per-pass", str(PHOTONS), "-q", "-o", str(cli_out)],
        check=True,
    )
    table, rel_mse, mean_ratio = compare(engine_out, cli_out)
    print(table)
    assert abs(mean_ratio - 1.0) < 0.03, table


def smoke_volume_stage():
    """A Volume object reading a Blender-written OpenVDB smoke cache (the test fixture),
    moved, turned and scaled, with a Principled Volume of density 20, on a floor under a spot
    light."""
    scene = floor_stage()
    volume = bpy.data.volumes.new("plume")
    volume.filepath = str(ROOT / "tests" / "fixtures" / "vdb" / "smoke_blosc_half_f24.vdb")
    obj = bpy.data.objects.new("plume", volume)
    scene.collection.objects.link(obj)
    obj.location = (-0.4, 0.3, 0.0)
    obj.rotation_euler = (0.0, 0.0, math.radians(30))
    obj.scale = (0.8, 0.8, 0.8)
    volume.materials.append(principled_volume(
        "smoke", Color=(0.9, 0.85, 0.8, 1.0), Density=20.0,
        **{"Absorption Color": (0.0, 0.0, 0.0, 1.0)}))
    bpy.ops.object.light_add(type="SPOT", location=(0, 0, 3.5), rotation=(0, 0, 0))
    spot = bpy.context.active_object.data
    spot.energy, spot.spot_size, spot.spot_blend = 400.0, math.radians(60), 0.0
    bpy.ops.object.camera_add(location=(0, -4.5, 1.0), rotation=(math.radians(85), 0, 0))
    scene.camera = bpy.context.active_object
    scene.camera.data.angle = math.radians(45)
    return scene, obj


def test_a_volume_object_maps_to_a_grid_medium_in_its_place(tmp_path):
    import tomllib

    scene, obj = smoke_volume_stage()
    reports = []
    depsgraph = bpy.context.evaluated_depsgraph_get()
    path, _ = photon_blender.export_scene(depsgraph, str(tmp_path), reports.append)
    with open(path, "rb") as f:
        toml = tomllib.load(f)
    assert reports == [], reports
    medium = toml["media"]["plume grid"]
    assert medium["grid"] == "volume0.vdb" and medium["grid_name"] == "density"
    source = Path(bpy.path.abspath(obj.data.filepath))
    assert (tmp_path / "volume0.vdb").read_bytes() == source.read_bytes()
    # Cycles' Principled Volume per unit of the grid: σs = colour · density.
    assert medium["sigma_s"] == pytest.approx([18.0, 17.0, 16.0])
    box = next(s for s in toml["shapes"] if s.get("interior") == "plume grid")
    assert box["type"] == "box" and "material" not in box
    # Where the smoke is (the grid in the object's space, Blender's z-up world turned y-up): a
    # path render of the export differs from the stage without it mostly inside the image of
    # the object's bounds, as Blender's own camera projects them.
    from bpy_extras.object_utils import world_to_camera_view

    def render(scene_file, out):
        subprocess.run([photon_cli(), "render", scene_file, "--integrator", "path", "--spp", "16",
                        "--width", "32", "--height", "32", "-q", "-o", str(out)], check=True)

    render(path, tmp_path / "with.pfm")
    empty = tmp_path / "empty.toml"
    text = Path(path).read_text().replace('interior = "plume grid"', 'interior = "none"')
    empty.write_text(text + '\n[media.none]\nsigma_s = 0.0\n')
    render(str(empty), tmp_path / "without.pfm")
    with_smoke = read_pfm(tmp_path / "with.pfm").sum(axis=2)
    without = read_pfm(tmp_path / "without.pfm").sum(axis=2)
    bounds = obj.evaluated_get(depsgraph).bound_box
    corners = [world_to_camera_view(scene, scene.camera, obj.matrix_world @ mathutils.Vector(c))
               for c in bounds]
    x0, x1 = min(c.x for c in corners) * 32, max(c.x for c in corners) * 32
    y0, y1 = (1 - max(c.y for c in corners)) * 32, (1 - min(c.y for c in corners)) * 32
    changed = np.argwhere(np.abs(with_smoke - without) > 0.05 * (without + 0.05))
    assert len(changed) > 20, "the smoke is not seen"
    inside = [(y, x) for y, x in changed if x0 - 1 <= x <= x1 + 1 and y0 - 1 <= y <= y1 + 1]
    # The smoke's shadow on the floor may fall outside its own box.
    assert len(inside) > 0.5 * len(changed), (len(inside), len(changed), (x0, x1, y0, y1))


def glb_json(path):
    """The JSON chunk of a GLB file."""
    data = Path(path).read_bytes()
    length = int.from_bytes(data[12:16], "little")
    assert data[:4] == b"glTF" and data[16:20] == b"JSON"
    return json.loads(data[20:20 + length])


def test_a_glass_dispersion_reaches_photon_as_its_abbe_number(tmp_path):
    """Blender (4.5, 5.0) has no dispersion of its own: no Dispersion input on the Principled
    BSDF, and no KHR_materials_dispersion from its glTF exporter. The add-on takes it, as newer
    glTF exporters do, from the Dispersion input (glTF's 20 / V_d) of the material's glTF
    Material Output group, and writes it into the export. Photon renders that glass (spectral)
    bit for bit as the TOML glass of the same index and Abbe number, and unlike the glass
    without dispersion."""
    v_d, ior = 40.0, 1.5
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = 32
    scene.render.resolution_percentage = 100
    glass = principled("crystal", (1, 1, 1), roughness=0.0,
                       **{"Transmission Weight": 1.0, "IOR": ior})
    # The glTF add-on's settings group (Add > Output > glTF Material Output), as newer
    # Blenders make it: Occlusion, Thickness (KHR_materials_volume), Dispersion.
    group = bpy.data.node_groups.new("glTF Material Output", "ShaderNodeTree")
    for name in ("Occlusion", "Thickness", "Dispersion"):
        group.interface.new_socket(name, socket_type="NodeSocketFloat")
    settings = glass.node_tree.nodes.new("ShaderNodeGroup")
    settings.node_tree = group
    settings.inputs["Dispersion"].default_value = 20.0 / v_d
    # A glass ball in front of a square area light, which it images with coloured edges.
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.5)
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(glass)
    bpy.ops.object.light_add(type="AREA", location=(0, 1.5, 0), rotation=(-math.pi / 2, 0, 0))
    light = bpy.context.active_object.data
    light.shape, light.size, light.energy = "SQUARE", 0.6, 20.0
    bpy.ops.object.camera_add(location=(0, -3, 0), rotation=(math.pi / 2, 0, 0))
    scene.camera = bpy.context.active_object
    scene.camera.data.angle = math.radians(30)
    reports = []
    path, _ = photon_blender.export_scene(
        bpy.context.evaluated_depsgraph_get(), str(tmp_path), reports.append
    )
    assert reports == [], reports
    doc = glb_json(tmp_path / "meshes.glb")
    (material,) = doc["materials"]
    assert material["extensions"]["KHR_materials_dispersion"]["dispersion"] == pytest.approx(
        20.0 / v_d
    )
    assert "KHR_materials_dispersion" in doc["extensionsUsed"]
    assert material.get("extensions", {}).get("KHR_materials_ior", {"ior": 1.5})["ior"] == ior
    # The Spectral setting asks the integrator for spectral rendering.
    spectral = types.SimpleNamespace(integrator="path", seed=0, max_depth=0, spp=0, spectral=True)
    assert photon_blender.options(spectral)["spectral"] is True

    # Photon: the export, and the same scene with the ball's glass given in TOML.
    text = Path(path).read_text()
    mesh = 'file = "meshes.glb"\n'
    assert mesh in text

    def render(name, glass_toml=None):
        scene_file = tmp_path / f"{name}.toml"
        if glass_toml is None:
            scene_file.write_text(text)
        else:
            scene_file.write_text(text.replace(mesh, mesh + 'material = "glass"\n')
                                  + '\n[materials.glass]\ntype = "glass"\n' + glass_toml)
        out = tmp_path / f"{name}.pfm"
        subprocess.run([photon_cli(), "render", str(scene_file), "--integrator", "path",
                        "--spp", "32", "--spectral", "-q", "-o", str(out)], check=True)
        return out

    exported = render("exported")
    same = render("abbe", f"ior = {ior}\nabbe = {v_d}\n")
    plain = render("plain", f"ior = {ior}\n")
    assert np.array_equal(read_pfm(exported), read_pfm(same))
    table, rel_mse, _ = compare(exported, plain)
    assert rel_mse > 0.01, table
