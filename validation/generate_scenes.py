#!/usr/bin/env python3
"""Write the validation scenes: for every scene NAME, NAME/NAME.toml (Photon) and NAME/NAME.xml
(Mitsuba 3), plus the small assets they share (PNG texture, PLY/OBJ meshes).

Both files are written from one description here, so the two renderers see the same geometry,
materials and lights. Edit this file, not the generated ones, then run

    python validation/generate_scenes.py            # all scenes
    python validation/generate_scenes.py NAME ...   # some
    python validation/make_references.py NAME ...   # their Mitsuba references

Only the Python standard library is needed (numpy is used if present, for nothing essential).

Conventions (checked scene by scene against Photon's `path` integrator, see README.md):
- camera: Photon `position/look_at/up/fov` (vertical, degrees) = Mitsuba `lookat` +
  `fov_axis="y"`; both put +x on the right when looking down -z with +y up.
- diffuse = Mitsuba `twosided(diffuse)` (Photon's Lambertian is two-sided; Mitsuba's is not).
- mirror = Mitsuba `twosided(conductor material="none")` with `specular_reflectance`.
- glass = Mitsuba `dielectric` with `int_ior` = ior and `ext_ior` = 1 (not Mitsuba's default air).
- quads are parallelograms here, written as Mitsuba `rectangle`s whose to_world columns are the
  two half-edges and the normal (v1 - v0) x (v3 - v0): the side Photon's one-sided emitters light.
- emitters carry a black diffuse BSDF in Mitsuba (Photon lights without a material reflect
  nothing; Mitsuba's default BSDF is a 0.5 grey diffuse), or their material's when they have one.
  A two-sided quad light with a material is two rectangles 0.1 mm either side of the quad.
- spot lights: a hard cone (Photon `falloff = 0`, Mitsuba `beam_width = cutoff_angle`): the two
  soft-edge profiles differ (smoothstep in cos theta vs linear in angle) and cannot be matched.
- meshes without normals are flat in Photon: Mitsuba gets `face_normals = true`.
- conductor = Mitsuba `twosided(roughconductor)` (`conductor` when alpha = 0) with the preset
  `material` (gold Au, silver Ag, copper Cu, aluminium Al) and distribution `ggx`.
- rough glass (alpha > 0) = Mitsuba `roughdielectric`, `ggx`, `int_ior` = ior, `ext_ior` = 1.
- pbr (glTF 2.0 metallic-roughness) = `twosided(gltf_pbr)`, the Python plugin in gltf_pbr.py.
- environment light = Mitsuba `envmap` (`scale` = intensity, to_world = rotate about +y), or
  `constant` for a uniform radiance. The sky image comes from make_sky.py.

Participating media (the scenes fog-spot, fog-box, absorbing-water, thick-medium,
volumetric-caustic, smoke-grid; Mitsuba integrator `volpath`, max_depth -1, chosen automatically
when a scene defines a medium, `Scene.integrator` overrides it):
- Photon `[media.NAME]` with `sigma_a`, `sigma_s` (per scene unit, number or RGB) and `g`, or
  Mitsuba's form `albedo` + `density` (sigma_s = albedo * density, sigma_a = (1 - albedo) *
  density) = Mitsuba `homogeneous` with sigma_t = sigma_a + sigma_s and albedo = sigma_s /
  sigma_t per channel. Mitsuba wants RGB values in [0, 1]: a coloured sigma_t is written as the
  colour over its largest channel times `scale` (a grey one as a float).
- a grid medium (`grid`, `grid_name`, `transform` in `[media.NAME]`: the coefficients per unit
  density) = Mitsuba `heterogeneous` with a `gridvolume` sigma_t read from a .vol of the same
  dense box (vdb_to_vol.py converts a .vdb), `scale` = sigma_t per unit density (grey), the
  albedo as above; the gridvolume's to_world = Photon's transform x the file's own placement
  (class Grid). The medium's boundary coincides with the grid's cube (density zero outside).
- phase: g != 0 = Mitsuba `hg` with `g` written always (Mitsuba's default g is 0.8, not 0);
  g = 0 = `isotropic`. Both put g > 0 forward (checked: hg's value for the straight-on direction
  is (1 - g^2) / (4 pi (1 - g)^3)).
- the scene's medium (Photon's top-level `medium = "NAME"`): the sensor's `<ref name="medium">`
  (volpath starts camera rays in it); point and spot lights get the same ref (volpath does not
  use it: it tracks the medium from the shading point; it is there for completeness).
- a shape with `interior`/`exterior`: Mitsuba `<ref name="interior">`/`<ref name="exterior">`.
  Photon's exterior defaults to the scene's medium, Mitsuba's to vacuum: the XML always writes
  the exterior explicitly. Without a material the shape is an invisible boundary: Mitsuba's
  `null` BSDF (otherwise it would get the default grey diffuse). With a material (glass) it is a
  refracting boundary (Mitsuba's `dielectric` with the medium refs). Shapes with neither keep
  the medium the ray is in, in both renderers (Mitsuba: no medium transition).
- the side: both take the interior as the side opposite the geometric normal (a ray leaving
  along the normal goes to the exterior: Mitsuba's `target_medium`, Photon's `medium_after`);
  spheres and boxes (Mitsuba `cube`) face outward.
- a medium whose coefficients are all zero (`air` in volumetric-caustic: the clear inside of a
  glass sphere in fog) is written to Mitsuba as vacuum (no medium object, no ref).
- shadow rays: Mitsuba's volpath passes null surfaces (with the media's transmittance) and
  stops at any other surface, glass included, as Photon's.
- boundaries never touch other surfaces: a medium box standing on the floor reaches 1 cm below
  it (the floor cuts it), the glass box of water stands 2 mm above the floor.
"""

import math
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RES = 128

# --------------------------------------------------------------------------------------------
# Small vector helpers (no numpy needed)


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def mul(a, s):
    return [a[i] * s for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    return mul(a, 1.0 / norm(a))


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def identity():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def m_translate(t):
    m = identity()
    for i in range(3):
        m[i][3] = t[i]
    return m


def m_scale(s):
    if not isinstance(s, (list, tuple)):
        s = [s, s, s]
    m = identity()
    for i in range(3):
        m[i][i] = s[i]
    return m


def m_rotate(axis, deg):
    """Right-handed rotation (Rodrigues), as Photon's `rotate = { axis, angle }`."""
    x, y, z = unit(axis)
    a = math.radians(deg)
    c, s = math.cos(a), math.sin(a)
    t = 1 - c
    return [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.0],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]


def compose(tables):
    """Photon's transform list: each table is scale, then rotate, then translate; the list is
    applied first to last. Returns the 4x4 object-to-world matrix."""
    m = identity()
    for t in tables:
        step = identity()
        if "scale" in t:
            step = matmul(m_scale(t["scale"]), step)
        if "rotate" in t:
            step = matmul(m_rotate(t["rotate"]["axis"], t["rotate"]["angle"]), step)
        if "translate" in t:
            step = matmul(m_translate(t["translate"]), step)
        m = matmul(step, m)
    return m


def xform_point(m, p):
    return [sum(m[i][k] * p[k] for k in range(3)) + m[i][3] for i in range(3)]


# --------------------------------------------------------------------------------------------
# Formatting


def fnum(x):
    x = float(x)
    if x == int(x) and abs(x) < 1e15:
        return f"{x:.1f}"
    return repr(round(x, 9))


def tvec(v):
    if not isinstance(v, (list, tuple)):
        return fnum(v)
    return "[" + ", ".join(fnum(x) for x in v) + "]"


def xvec(v):
    if not isinstance(v, (list, tuple)):
        v = [v, v, v]
    return ", ".join(fnum(x) for x in v)


def xmatrix(m):
    return " ".join(fnum(m[i][j]) for i in range(4) for j in range(4))


def rgb3(c):
    return list(c) if isinstance(c, (list, tuple)) else [c, c, c]


# --------------------------------------------------------------------------------------------
# Density grids


class Grid:
    """A density grid of a heterogeneous medium, placed alike in both renderers.

    Both fill the unit cube with the grid (voxel (i, j, k) of n_x x n_y x n_z centred at
    ((i + 1/2) / n_x, ...), trilinear between centres, held flat to the faces). Photon reads
    `file` (with `grid_name`): a .vdb puts the cube over the active voxels' box in the file's
    world (`file_placement`, the 4 x 4 unit-cube-to-file-world affine vdb_to_vol.py prints), a
    .vol in its own space (identity); then Photon's `transform` (a list of tables, `compose`)
    applies. Mitsuba reads `vol_file`, the same dense box as a .vol (vdb_to_vol.py), with the
    gridvolume's to_world = compose(transform) x file_placement."""

    def __init__(self, file, vol_file, transform, file_placement=None, name="density"):
        self.file = file
        self.vol_file = vol_file
        self.name = name
        self.transform = transform
        self.file_placement = file_placement or identity()

    def unit_to_world(self):
        return matmul(compose(self.transform), self.file_placement)

    def world_box(self):
        """The unit cube's (min, max) corners in the world; it must stay axis-aligned."""
        m = self.unit_to_world()
        for i in range(3):
            assert sum(abs(m[i][j]) > 1e-12 for j in range(3)) == 1, "the grid's cube is not axis-aligned"
        corners = [xform_point(m, [float(c >> a & 1) for a in range(3)]) for c in range(8)]
        return [min(p[i] for p in corners) for i in range(3)], [max(p[i] for p in corners) for i in range(3)]


# --------------------------------------------------------------------------------------------
# Scene description


class Scene:
    def __init__(self, name, comment):
        self.name = name
        self.comment = comment
        self.camera = None
        self.materials = {}  # name -> dict
        self.shapes = []  # (toml lines, xml text)
        self.lights = []
        self.spp = 16
        self.ref_spp = 1024
        self.assets = {}  # file name -> bytes
        self.media = {}  # name -> dict (see define_medium)
        self.scene_medium = None  # the medium around every shape (camera, point and spot lights)
        self.integrator = None  # Mitsuba integrator; default: volpath if there are media, else path
        # The reference's file name: scenes made for a study, not for the suite, keep theirs
        # apart (a scene with reference.exr joins `photon validate` and the tests).
        self.reference_file = "reference.exr"

    # camera --------------------------------------------------------------------------------
    def set_camera(self, position, look_at, up=(0.0, 1.0, 0.0), fov=40.0):
        self.camera = dict(position=list(position), look_at=list(look_at), up=list(up), fov=fov)

    # materials -----------------------------------------------------------------------------
    def diffuse(self, name, albedo=None, texture=None):
        self.materials[name] = dict(type="diffuse", albedo=albedo, texture=texture)

    def mirror(self, name, reflectance=1.0):
        self.materials[name] = dict(type="mirror", reflectance=reflectance)

    def glass(self, name, ior, alpha=0.0):
        self.materials[name] = dict(type="glass", ior=ior, alpha=alpha)

    def conductor(self, name, metal, alpha=0.0):
        assert metal in METALS, metal
        self.materials[name] = dict(type="conductor", metal=metal, alpha=alpha)

    def pbr(self, name, base_color, metallic=0.0, roughness=0.5):
        self.materials[name] = dict(type="pbr", base_color=base_color, metallic=metallic, roughness=roughness)

    # media ---------------------------------------------------------------------------------
    def define_medium(self, name, sigma_a=None, sigma_s=None, g=0.0, albedo=None, density=None, grid=None):
        """A medium `[media.NAME]`: either sigma_a and sigma_s (per scene unit, a number or RGB),
        or Mitsuba's albedo (number or RGB) and density (a number). g is the Henyey-Greenstein
        asymmetry (0: isotropic). Homogeneous, or with `grid` (a `Grid`) heterogeneous: the
        coefficients are per unit of the grid's density."""
        assert (albedo is None) == (density is None) and (albedo is None) != (sigma_a is None and sigma_s is None)
        assert -1.0 < g < 1.0
        if albedo is not None:
            sa = [(1.0 - a) * density for a in rgb3(albedo)]
            ss = [a * density for a in rgb3(albedo)]
        else:
            sa, ss = rgb3(sigma_a or 0.0), rgb3(sigma_s or 0.0)
        if grid is not None:
            # Mitsuba's heterogeneous sigma_t is the grid times a float `scale`: a grey extinction.
            sigma_t = [a + b for a, b in zip(sa, ss)]
            assert max(sigma_t) > 0 and max(sigma_t) == min(sigma_t), "grid media need a grey sigma_t"
        self.media[name] = dict(sigma_a=sigma_a, sigma_s=sigma_s, albedo=albedo, density=density, g=g,
                                sa=sa, ss=ss, grid=grid)

    def set_medium(self, name):
        """The scene's medium (Photon's top-level `medium`). Call before adding shapes and lights:
        Mitsuba's shapes get it as their explicit exterior, its point and spot lights as theirs."""
        assert name in self.media and not self.shapes and not self.lights
        self.scene_medium = name

    def _is_vacuum(self, name):
        """A medium of zero coefficients is written to Mitsuba as vacuum (no medium object)."""
        return name is None or all(x == 0.0 for x in self.media[name]["sa"] + self.media[name]["ss"])

    def _toml_media(self, interior, exterior):
        out = []
        if interior is not None:
            assert interior in self.media, interior
            out.append(f'interior = "{interior}"')
        if exterior is not None:
            assert exterior in self.media, exterior
            out.append(f'exterior = "{exterior}"')
        return out

    def _xml_media(self, interior, exterior):
        """Mitsuba's interior/exterior refs. Photon's default exterior is the scene's medium;
        Mitsuba's is vacuum, so it is written explicitly. A shape with neither keeps the ray's
        medium in both renderers (no medium transition)."""
        if interior is None and exterior is None:
            return ""
        ext = exterior if exterior is not None else self.scene_medium
        out = ""
        if not self._is_vacuum(interior):
            out += f'    <ref name="interior" id="{interior}"/>\n'
        if not self._is_vacuum(ext):
            out += f'    <ref name="exterior" id="{ext}"/>\n'
        return out

    def _xml_endpoint_medium(self):
        if self._is_vacuum(self.scene_medium):
            return ""
        return f'    <ref name="medium" id="{self.scene_medium}"/>\n'

    # shapes --------------------------------------------------------------------------------
    def _toml_emission(self, emission):
        if emission is None:
            return []
        kind, value = emission
        return [f"emission = {{ {kind} = {tvec(value)} }}"]

    def _xml_emitter(self, radiance, material=None):
        """The area emitter, with the emitting shape's BSDF: its material's if it has one (the
        emitter reflects, as in Photon), else black."""
        if radiance is None:
            return ""
        bsdf = (f'    <ref id="{material}"/>\n' if material
                else '    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>\n')
        return '    <emitter type="area"><rgb name="radiance" value="%s"/></emitter>\n' % xvec(radiance) + bsdf

    def _xml_bsdf(self, material, radiance, interface=False):
        if radiance is not None:
            return ""
        if material is None and interface:
            # A medium boundary without a material: invisible (Mitsuba's null BSDF, pbrt's
            # "interface"); without it Mitsuba would give the shape a grey diffuse BSDF.
            return '    <bsdf type="null"/>\n'
        return f'    <ref id="{material}"/>\n'

    @staticmethod
    def _radiance(emission, area, sides=1):
        if emission is None:
            return None
        kind, value = emission
        if kind == "radiance":
            return rgb3(value)
        return [p / (sides * math.pi * area) for p in rgb3(value)]

    def quad(self, v, material=None, emission=None, light=False, two_sided=False):
        """A parallelogram v0, v1, v2, v3 (counter-clockwise seen from its front).
        `light=True` writes it as a [[lights]] quad (emission given as power or radiance);
        `two_sided=True` makes it emit from both faces (Mitsuba: two rectangles back to back; with
        a `material`, which they reflect, 0.1 mm either side of the quad, as blender_scenes.py
        writes its two-sided lamps, so that a ray finds the face it arrives at)."""
        v = [list(map(float, p)) for p in v]
        e1, e3 = sub(v[1], v[0]), sub(v[3], v[0])
        assert norm(sub(add(v[0], add(e1, e3)), v[2])) < 1e-9 * max(1.0, norm(e1)), "not a parallelogram"
        assert abs(dot(e1, e3)) < 1e-9 * norm(e1) * norm(e3), "Mitsuba rectangles need right angles"
        n = unit(cross(e1, e3))
        c = mul(add(v[0], v[2]), 0.5)
        a, b = mul(e1, 0.5), mul(e3, 0.5)
        m = [[a[i], b[i], n[i], c[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]]
        area = norm(cross(e1, e3))
        rad = self._radiance(emission, area, 2 if two_sided else 1)
        verts = "[" + ", ".join(tvec(p) for p in v) + "]"
        if light:
            kind, value = emission
            toml = ["[[lights]]", 'type = "quad"', f"vertices = {verts}", f"{kind} = {tvec(value)}"]
            if two_sided:
                toml.append("two_sided = true")
            if material:
                toml.append(f'material = "{material}"')
        else:
            toml = ["[[shapes]]", 'type = "quad"', f"vertices = {verts}"]
            if material:
                toml.append(f'material = "{material}"')
            toml += self._toml_emission(emission)
        def rectangle(matrix):
            return (
                '<shape type="rectangle">\n'
                f'    <transform name="to_world"><matrix value="{xmatrix(matrix)}"/></transform>\n'
                + self._xml_bsdf(material, rad)
                + self._xml_emitter(rad, material)
                + "</shape>"
            )

        if two_sided and material:
            # Two reflecting faces: coincident, a ray could stop at the back one (no emission
            # toward it) or leave one face to meet the other at once. 0.1 mm either side.
            front = add(c, mul(n, 1e-4))
            back = sub(c, mul(n, 1e-4))
            xml = rectangle([[a[i], b[i], n[i], front[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]])
            xml += "\n" + rectangle([[a[i], b[i], -n[i], back[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]])
        else:
            xml = rectangle(m)
        if two_sided and not material:
            # The back face: the same rectangle with its normal (the matrix's z column) negated.
            xml += "\n" + rectangle([[a[i], b[i], -n[i], c[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]])
        (self.lights if light else self.shapes).append((toml, xml))

    def sphere(self, center, radius, material=None, emission=None, interior=None, exterior=None):
        """A sphere; `interior`/`exterior` name the media inside and outside it (a sphere with
        media and no material is an invisible boundary)."""
        area = 4 * math.pi * radius * radius
        rad = self._radiance(emission, area)
        interface = interior is not None or exterior is not None
        assert material or emission or interface
        toml = ["[[shapes]]", 'type = "sphere"', f"center = {tvec(center)}", f"radius = {fnum(radius)}"]
        if material:
            toml.append(f'material = "{material}"')
        toml += self._toml_emission(emission)
        toml += self._toml_media(interior, exterior)
        xml = (
            '<shape type="sphere">\n'
            f'    <point name="center" value="{xvec(center)}"/>\n'
            f'    <float name="radius" value="{fnum(radius)}"/>\n'
            + self._xml_bsdf(material, rad, interface)
            + self._xml_emitter(rad, material)
            + self._xml_media(interior, exterior)
            + "</shape>"
        )
        self.shapes.append((toml, xml))

    def disk(self, center, normal, radius, material):
        n = unit(normal)
        # Any frame with z = n: the disk is rotationally symmetric.
        t = [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]
        s = unit(cross(t, n))
        t = cross(n, s)
        m = [[s[i] * radius, t[i] * radius, n[i] * radius, center[i]] for i in range(3)]
        m.append([0.0, 0.0, 0.0, 1.0])
        toml = [
            "[[shapes]]",
            'type = "disk"',
            f"center = {tvec(center)}",
            f"normal = {tvec(normal)}",
            f"radius = {fnum(radius)}",
            f'material = "{material}"',
        ]
        xml = (
            '<shape type="disk">\n'
            f'    <transform name="to_world"><matrix value="{xmatrix(m)}"/></transform>\n'
            f'    <ref id="{material}"/>\n'
            "</shape>"
        )
        self.shapes.append((toml, xml))

    def box(self, size, material, rotate_y=0.0, translate=(0.0, 0.0, 0.0), interior=None, exterior=None):
        """A box of `size` centred on the origin, turned about +y, then moved: Photon `box` with
        a transform, Mitsuba `cube` ([-1, 1]^3, normals outward) with the same matrix times the
        half-size. `interior`/`exterior`: media (with `material = None`: an invisible boundary)."""
        h = [s / 2 for s in size]
        tables = [{"rotate": {"axis": [0.0, 1.0, 0.0], "angle": rotate_y}, "translate": list(translate)}]
        m = matmul(compose(tables), m_scale(h))
        interface = interior is not None or exterior is not None
        assert material or interface
        toml = [
            "[[shapes]]",
            'type = "box"',
            f"min = {tvec([-x for x in h])}",
            f"max = {tvec(h)}",
        ]
        if material:
            toml.append(f'material = "{material}"')
        toml += self._toml_media(interior, exterior)
        toml.append(
            "transform = { rotate = { axis = [0.0, 1.0, 0.0], angle = %s }, translate = %s }"
            % (fnum(rotate_y), tvec(translate))
        )
        xml = (
            '<shape type="cube">\n'
            f'    <transform name="to_world"><matrix value="{xmatrix(m)}"/></transform>\n'
            + self._xml_bsdf(material, None, interface)
            + self._xml_media(interior, exterior)
            + "</shape>"
        )
        self.shapes.append((toml, xml))

    def mesh(self, file, material, tables, flat, xml_file=None, smooth=None):
        """A mesh file with Photon's transform list `tables`. `flat`: the file has no normals
        (Mitsuba would otherwise compute smooth ones)."""
        m = compose(tables)
        toml = ["[[shapes]]", 'type = "mesh"', f'file = "{file}"', f'material = "{material}"']
        if smooth is not None:
            toml.append(f"smooth = {'true' if smooth else 'false'}")
        toml.append("transform = " + toml_transform(tables))
        xf = xml_file or file
        kind = "obj" if xf.endswith(".obj") else "ply"
        xml = (
            f'<shape type="{kind}">\n'
            f'    <string name="filename" value="{xf}"/>\n'
            + ('    <boolean name="face_normals" value="true"/>\n' if flat else "")
            + ('    <boolean name="flip_tex_coords" value="false"/>\n' if kind == "obj" else "")
            + f'    <transform name="to_world"><matrix value="{xmatrix(m)}"/></transform>\n'
            f'    <ref id="{material}"/>\n'
            "</shape>"
        )
        self.shapes.append((toml, xml))

    def raw(self, toml, xml):
        self.shapes.append((toml, xml))

    # lights --------------------------------------------------------------------------------
    def point(self, position, power=None, intensity=None):
        if power is not None:
            i = [p / (4 * math.pi) for p in rgb3(power)]
            line = f"power = {tvec(power)}"
        else:
            i = rgb3(intensity)
            line = f"intensity = {tvec(intensity)}"
        toml = ["[[lights]]", 'type = "point"', f"position = {tvec(position)}", line]
        xml = (
            '<emitter type="point">\n'
            f'    <point name="position" value="{xvec(position)}"/>\n'
            f'    <rgb name="intensity" value="{xvec(i)}"/>\n'
            + self._xml_endpoint_medium()
            + "</emitter>"
        )
        self.lights.append((toml, xml))

    def spot(self, position, look_at, intensity, angle):
        d = unit(sub(look_at, position))
        up = [0.0, 1.0, 0.0] if abs(d[1]) < 0.9 else [1.0, 0.0, 0.0]
        toml = [
            "[[lights]]",
            'type = "spot"',
            f"position = {tvec(position)}",
            f"look_at = {tvec(look_at)}",
            f"intensity = {tvec(intensity)}",
            f"angle = {fnum(angle)}",
            "falloff = 0.0",
        ]
        xml = (
            '<emitter type="spot">\n'
            f'    <transform name="to_world"><lookat origin="{xvec(position)}" target="{xvec(look_at)}" up="{xvec(up)}"/></transform>\n'
            f'    <rgb name="intensity" value="{xvec(intensity)}"/>\n'
            f'    <float name="cutoff_angle" value="{fnum(angle)}"/>\n'
            f'    <float name="beam_width" value="{fnum(angle)}"/>\n'
            + self._xml_endpoint_medium()
            + "</emitter>"
        )
        self.lights.append((toml, xml))

    def directional(self, direction, irradiance):
        toml = [
            "[[lights]]",
            'type = "directional"',
            f"direction = {tvec(direction)}",
            f"irradiance = {tvec(irradiance)}",
        ]
        xml = (
            '<emitter type="directional">\n'
            f'    <vector name="direction" value="{xvec(direction)}"/>\n'
            f'    <rgb name="irradiance" value="{xvec(irradiance)}"/>\n'
            "</emitter>"
        )
        self.lights.append((toml, xml))

    def environment(self, file=None, radiance=None, intensity=1.0, rotate=0.0):
        """An environment light: an equirectangular image `file` (Mitsuba `envmap`, `scale` =
        intensity, turned by `rotate` degrees about +y) or a uniform `radiance` (`constant`)."""
        toml = ["[[lights]]", 'type = "environment"']
        if file:
            toml.append(f'file = "{file}"')
            xml = (
                '<emitter type="envmap">\n'
                f'    <string name="filename" value="{file}"/>\n'
                f'    <float name="scale" value="{fnum(intensity)}"/>\n'
                f'    <transform name="to_world"><rotate y="1" angle="{fnum(rotate)}"/></transform>\n'
                "</emitter>"
            )
        else:
            toml.append(f"radiance = {tvec(radiance)}")
            xml = (
                '<emitter type="constant">\n'
                f'    <rgb name="radiance" value="{xvec([c * intensity for c in rgb3(radiance)])}"/>\n'
                "</emitter>"
            )
        toml += [f"intensity = {fnum(intensity)}", f"rotate = {fnum(rotate)}"]
        self.lights.append((toml, xml))

    # output --------------------------------------------------------------------------------
    def toml(self):
        c = self.camera
        out = [f"# {line}".rstrip() for line in self.comment.strip().splitlines()]
        out += [
            "# Written by validation/generate_scenes.py (edit there); Mitsuba twin: "
            f"{self.name}.xml, reference: {self.reference_file}.",
            f'name = "{self.name}"',
        ]
        if self.scene_medium:
            out.append(f'medium = "{self.scene_medium}"')
        out += [
            "",
            "[camera]",
            f"position = {tvec(c['position'])}",
            f"look_at = {tvec(c['look_at'])}",
            f"up = {tvec(c['up'])}",
            f"fov = {fnum(c['fov'])}",
            f"resolution = [{RES}, {RES}]",
            "",
            "[render]",
            f"spp = {self.spp}",
            'filter = "box"',
            "",
        ]
        for name, m in self.materials.items():
            out.append(f"[materials.{name}]")
            out.append(f'type = "{m["type"]}"')
            if m["type"] == "diffuse":
                if m["texture"]:
                    out.append(f'albedo = {{ texture = "{m["texture"]}" }}')
                else:
                    out.append(f"albedo = {tvec(m['albedo'])}")
            elif m["type"] == "mirror":
                out.append(f"reflectance = {tvec(m['reflectance'])}")
            elif m["type"] == "conductor":
                out.append(f'metal = "{m["metal"]}"')
                out.append(f"alpha = {fnum(m['alpha'])}")
            elif m["type"] == "pbr":
                out.append(f"base_color = {tvec(rgb3(m['base_color']))}")
                out.append(f"metallic = {fnum(m['metallic'])}")
                out.append(f"roughness = {fnum(m['roughness'])}")
            else:
                out.append(f"ior = {fnum(m['ior'])}")
                if m["alpha"]:
                    out.append(f"alpha = {fnum(m['alpha'])}")
            out.append("")
        for name, m in self.media.items():
            out.append(f"[media.{name}]")
            if m["albedo"] is not None:
                out.append(f"albedo = {tvec(m['albedo'])}")
                out.append(f"density = {fnum(m['density'])}")
            else:
                out.append(f"sigma_a = {tvec(m['sigma_a'] or 0.0)}")
                out.append(f"sigma_s = {tvec(m['sigma_s'] or 0.0)}")
            out.append(f"g = {fnum(m['g'])}")
            if m["grid"] is not None:
                gr = m["grid"]
                out.append(f'grid = "{gr.file}"')
                out.append(f'grid_name = "{gr.name}"')
                if gr.transform:
                    out.append("transform = " + toml_transform(gr.transform))
            out.append("")
        for toml, _ in self.shapes + self.lights:
            out += toml + [""]
        return "\n".join(out)

    def xml(self):
        c = self.camera
        out = ['<?xml version="1.0" encoding="utf-8"?>']
        out += ["<!--"] + ["  " + line for line in self.comment.strip().splitlines()]
        out += [
            f"  Written by validation/generate_scenes.py (edit there); Photon twin: {self.name}.toml.",
            f"  Reference: python validation/make_references.py {self.name}"
            + ("" if self.reference_file == "reference.exr" else f" (writes {self.reference_file})"),
            "-->",
        ]
        if self.reference_file != "reference.exr":
            out.append(f"<!-- reference-file: {self.reference_file} -->")
        out += [
            '<scene version="3.0.0">',
            f'<default name="spp" value="{self.ref_spp}"/>',
            f'<integrator type="{self.integrator or ("volpath" if self.media else "path")}">'
            '<integer name="max_depth" value="-1"/></integrator>',
        ]
        # Media first: the shapes and the sensor refer to them.
        for name, m in self.media.items():
            if self._is_vacuum(name):
                out.append(f"<!-- medium {name}: zero coefficients, vacuum in Mitsuba (no medium object) -->")
                continue
            sigma_t = [a + b for a, b in zip(m["sa"], m["ss"])]
            albedo = [b / t if t > 0 else 0.0 for b, t in zip(m["ss"], sigma_t)]
            tmax = max(sigma_t)
            if min(sigma_t) == tmax:
                st = f'<float name="sigma_t" value="{fnum(tmax)}"/>'
            else:
                # Mitsuba's RGB values must lie in [0, 1]: the colour times `scale`.
                st = (f'<rgb name="sigma_t" value="{xvec([t / tmax for t in sigma_t])}"/>'
                      f'<float name="scale" value="{fnum(tmax)}"/>')
            if min(albedo) == max(albedo):
                al = f'<float name="albedo" value="{fnum(albedo[0])}"/>'
            else:
                al = f'<rgb name="albedo" value="{xvec(albedo)}"/>'
            # Mitsuba's hg defaults to g = 0.8: always written.
            phase = (f'<phase type="hg"><float name="g" value="{fnum(m["g"])}"/></phase>' if m["g"]
                     else '<phase type="isotropic"/>')
            if m["grid"] is not None:
                gr = m["grid"]
                st = (f'<volume name="sigma_t" type="gridvolume"><string name="filename" value="{gr.vol_file}"/>'
                      f'<transform name="to_world"><matrix value="{xmatrix(gr.unit_to_world())}"/></transform>'
                      f'</volume><float name="scale" value="{fnum(tmax)}"/>')
                out.append(f'<medium type="heterogeneous" id="{name}">{st}{al}{phase}</medium>')
                continue
            out.append(f'<medium type="homogeneous" id="{name}">{st}{al}{phase}</medium>')
        out += [
            '<sensor type="perspective">',
            f'    <float name="fov" value="{fnum(c["fov"])}"/>',
            '    <string name="fov_axis" value="y"/>',
            '    <float name="near_clip" value="0.001"/>',
            '    <float name="far_clip" value="1e7"/>',
            f'    <transform name="to_world"><lookat origin="{xvec(c["position"])}" '
            f'target="{xvec(c["look_at"])}" up="{xvec(c["up"])}"/></transform>',
            '    <sampler type="multijitter"><integer name="sample_count" value="$spp"/></sampler>',
        ]
        if not self._is_vacuum(self.scene_medium):
            out.append(f'    <ref name="medium" id="{self.scene_medium}"/>')
        out += [
            '    <film type="hdrfilm">',
            f'        <integer name="width" value="{RES}"/>',
            f'        <integer name="height" value="{RES}"/>',
            '        <string name="pixel_format" value="rgb"/>',
            '        <rfilter type="box"/>',
            "    </film>",
            "</sensor>",
        ]
        for name, m in self.materials.items():
            if m["type"] == "diffuse":
                if m["texture"]:
                    refl = (
                        '<texture type="bitmap" name="reflectance">'
                        f'<string name="filename" value="{m["texture"]}"/>'
                        '<string name="filter_type" value="bilinear"/>'
                        '<string name="wrap_mode" value="repeat"/>'
                        # Mitsuba looks v = 0 up in the image's first (top) row; Photon's v
                        # grows up the image: v -> 1 - v (and OBJ files are read unflipped).
                        '<transform name="to_uv"><scale x="1" y="-1"/><translate x="0" y="1"/></transform>'
                        '</texture>'
                    )
                else:
                    refl = f'<rgb name="reflectance" value="{xvec(m["albedo"])}"/>'
                out.append(f'<bsdf type="twosided" id="{name}"><bsdf type="diffuse">{refl}</bsdf></bsdf>')
            elif m["type"] == "mirror":
                out.append(
                    f'<bsdf type="twosided" id="{name}"><bsdf type="conductor">'
                    '<string name="material" value="none"/>'
                    f'<rgb name="specular_reflectance" value="{xvec(m["reflectance"])}"/></bsdf></bsdf>'
                )
            elif m["type"] == "conductor":
                preset = f'<string name="material" value="{METALS[m["metal"]]}"/>'
                if m["alpha"]:
                    inner = (
                        f'<bsdf type="roughconductor">{preset}<string name="distribution" value="ggx"/>'
                        f'<float name="alpha" value="{fnum(m["alpha"])}"/></bsdf>'
                    )
                else:
                    inner = f'<bsdf type="conductor">{preset}</bsdf>'
                out.append(f'<bsdf type="twosided" id="{name}">{inner}</bsdf>')
            elif m["type"] == "pbr":
                out.append(
                    f'<bsdf type="twosided" id="{name}"><bsdf type="gltf_pbr">'
                    f'<rgb name="base_color" value="{xvec(m["base_color"])}"/>'
                    f'<float name="metallic" value="{fnum(m["metallic"])}"/>'
                    f'<float name="roughness" value="{fnum(m["roughness"])}"/></bsdf></bsdf>'
                )
            elif m["alpha"]:
                out.append(
                    f'<bsdf type="roughdielectric" id="{name}"><string name="distribution" value="ggx"/>'
                    f'<float name="alpha" value="{fnum(m["alpha"])}"/>'
                    f'<float name="int_ior" value="{fnum(m["ior"])}"/><float name="ext_ior" value="1.0"/></bsdf>'
                )
            else:
                out.append(
                    f'<bsdf type="dielectric" id="{name}"><float name="int_ior" value="{fnum(m["ior"])}"/>'
                    '<float name="ext_ior" value="1.0"/></bsdf>'
                )
        for _, xml in self.shapes + self.lights:
            out.append(xml)
        out.append("</scene>")
        return "\n".join(out) + "\n"

    def write(self):
        d = os.path.join(HERE, self.name)
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, f"{self.name}.toml"), "w") as f:
            f.write(self.toml())
        with open(os.path.join(d, f"{self.name}.xml"), "w") as f:
            f.write(self.xml())
        for fname, data in self.assets.items():
            with open(os.path.join(d, fname), "wb") as f:
                f.write(data)


def toml_transform(tables):
    parts = []
    for t in tables:
        items = []
        if "scale" in t:
            items.append(f"scale = {tvec(t['scale'])}")
        if "rotate" in t:
            r = t["rotate"]
            items.append(f"rotate = {{ axis = {tvec(r['axis'])}, angle = {fnum(r['angle'])} }}")
        if "translate" in t:
            items.append(f"translate = {tvec(t['translate'])}")
        parts.append("{ " + ", ".join(items) + " }")
    return parts[0] if len(parts) == 1 else "[" + ", ".join(parts) + "]"


# --------------------------------------------------------------------------------------------
# Assets


def png_rgb8(width, height, pixels):
    """A PNG file (8-bit RGB, no colour profile: sRGB as both renderers assume) from rows of
    (r, g, b) tuples, top row first."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in pixels)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )


def ply_binary(positions, triangles, normals=None):
    """Binary little-endian PLY with float positions (and normals) and triangle faces."""
    props = ["x", "y", "z"] + (["nx", "ny", "nz"] if normals else [])
    head = "ply\nformat binary_little_endian 1.0\n"
    head += f"element vertex {len(positions)}\n" + "".join(f"property float {p}\n" for p in props)
    head += f"element face {len(triangles)}\nproperty list uchar int vertex_indices\nend_header\n"
    body = bytearray(head.encode())
    for i, p in enumerate(positions):
        vals = list(p) + (list(normals[i]) if normals else [])
        body += struct.pack("<" + "f" * len(vals), *vals)
    for t in triangles:
        body += struct.pack("<Biii", 3, *t)
    return bytes(body)


# --------------------------------------------------------------------------------------------
# Scenes

WHITE = [0.7, 0.7, 0.7]
# Photon's conductor presets and Mitsuba's names for them (Mitsuba's RGB eta, k: README.md).
METALS = {"gold": "Au", "silver": "Ag", "copper": "Cu", "aluminium": "Al"}
RED = [0.63, 0.065, 0.05]
GREEN = [0.14, 0.45, 0.091]


def room(s, x0=-1.0, x1=1.0, y0=0.0, y1=2.0, z0=-1.0, z1=1.0, left="red", right="green", walls="white",
         ceiling=True, front=False):
    """Floor, ceiling, back, left and right walls of an axis-aligned room, fronts facing in."""
    s.quad([[x0, y0, z1], [x1, y0, z1], [x1, y0, z0], [x0, y0, z0]], walls)  # floor, +y
    if ceiling:
        s.quad([[x0, y1, z0], [x1, y1, z0], [x1, y1, z1], [x0, y1, z1]], walls)  # ceiling, -y
    s.quad([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0]], walls)  # back, +z
    s.quad([[x0, y0, z1], [x0, y0, z0], [x0, y1, z0], [x0, y1, z1]], left)  # left, +x
    s.quad([[x1, y0, z0], [x1, y0, z1], [x1, y1, z1], [x1, y1, z0]], right)  # right, -x
    if front:
        s.quad([[x1, y0, z1], [x0, y0, z1], [x0, y1, z1], [x1, y1, z1]], walls)  # front, -z


def room_materials(s):
    s.diffuse("white", WHITE)
    s.diffuse("red", RED)
    s.diffuse("green", GREEN)


def std_camera(s):
    s.set_camera([0.0, 1.0, 3.8], [0.0, 1.0, 0.0], fov=39.3)


def low_camera(s, scale=1.0):
    """Closer and looking slightly down: a ceiling light (within 0.3 of the centre) stays out of
    the frame, so that its pixels do not carry most of the image's mean."""
    s.set_camera([0.0, 0.9 * scale, 2.7 * scale], [0.0, 0.55 * scale, 0.0], fov=39.3)


def point_light():
    s = Scene("point-light", """
Diffuse room (red left wall, green right) lit by one point light given by its power:
a turned box and a sphere cast hard shadows; everything else is interreflection.""")
    room_materials(s)
    s.diffuse("blue", [0.15, 0.25, 0.7])
    std_camera(s)
    room(s)
    s.box([0.5, 0.9, 0.5], "white", rotate_y=20.0, translate=[-0.4, 0.45, -0.3])
    s.sphere([0.45, 0.35, 0.2], 0.35, "blue")
    s.point([0.1, 1.7, 0.2], power=[40.0, 38.0, 34.0])
    s.ref_spp = 14336
    return s


def spot_light():
    s = Scene("spot-light", """
A spot light with a hard edge (falloff 0) aimed down into the room's far right corner: the cone
cuts across the floor, the back and right walls and a sphere; the rest of the room is lit only
by interreflection. Photon's soft edge (smoothstep in cos theta) has no Mitsuba counterpart
(Mitsuba's is linear in angle), so the edge is hard in both.""")
    room_materials(s)
    s.diffuse("yellow", [0.7, 0.6, 0.2])
    std_camera(s)
    room(s)
    s.sphere([0.25, 0.3, -0.35], 0.3, "yellow")
    s.spot([-0.5, 1.9, 0.6], [0.35, 0.0, -0.45], [14.0, 13.0, 11.0], 28.0)
    s.ref_spp = 12288
    return s


def directional():
    s = Scene("directional", """
The sun (a directional light) on a floor with a back and a left wall, open toward the light
(right, front and top): a box and a sphere cast shadows on the floor and the walls.""")
    s.diffuse("floor", [0.6, 0.6, 0.55])
    s.diffuse("wall", [0.7, 0.65, 0.6])
    s.diffuse("box", [0.2, 0.35, 0.6])
    s.diffuse("ball", [0.7, 0.3, 0.2])
    s.set_camera([2.2, 1.8, 3.4], [0.0, 0.4, -0.2], fov=45.0)
    x0, x1, z0, z1 = -1.2, 1.8, -1.2, 1.8
    s.quad([[x0, 0, z1], [x1, 0, z1], [x1, 0, z0], [x0, 0, z0]], "floor")
    s.quad([[x0, 0, z0], [x1, 0, z0], [x1, 1.5, z0], [x0, 1.5, z0]], "wall")
    s.quad([[x0, 0, z1], [x0, 0, z0], [x0, 1.5, z0], [x0, 1.5, z1]], "wall")
    s.box([0.5, 0.8, 0.5], "box", rotate_y=-25.0, translate=[-0.3, 0.4, -0.4])
    s.sphere([0.6, 0.3, 0.5], 0.3, "ball")
    s.directional([-0.8, -1.0, -0.45], [2.0, 1.9, 1.7])
    s.ref_spp = 2048
    return s


def grazing_area():
    s = Scene("grazing-area", """
A ceiling light (0.5 x 0.5) 1 mm below the ceiling, flush against the left wall and the open
front edge of the room: the left wall sees it at grazing angles, and a patch tilted 30 degrees
from vertical hangs 5 cm beside its footprint (its top edge 5 cm under the ceiling), facing the
light and the camera, lit at grazing incidence. The camera looks slightly down so that the
light itself is just out of the frame (its pixels would dominate the image mean).""")
    room_materials(s)
    s.set_camera([0.0, 1.0, 3.8], [0.0, 0.8, 0.0], fov=39.3)
    room(s)
    y = 2.0 - 1e-3
    s.quad([[-1.0, y, 0.5], [-0.5, y, 0.5], [-0.5, y, 1.0], [-1.0, y, 1.0]], emission=("radiance", [20.0, 19.0, 17.0]), light=True)
    t = math.radians(30.0)
    top = [0.0, 1.95, 0.45]
    down = [0.0, -math.cos(t) * 0.4, -math.sin(t) * 0.4]
    s.quad([add(top, [-0.95, 0, 0]), add(top, [-0.55, 0, 0]), add(add(top, down), [-0.55, 0, 0]),
            add(add(top, down), [-0.95, 0, 0])], "white")
    s.sphere([-0.45, 0.3, 0.1], 0.3, "white")
    s.box([0.4, 0.6, 0.4], "white", rotate_y=15.0, translate=[0.4, 0.3, -0.3])
    s.ref_spp = 16384
    return s


def curved_ceiling():
    s = Scene("curved-ceiling", """
Curved objects under a ceiling area light in a box (open at the front): two spheres and Photon's procedural
plant pot (`type = "pot"`, subdivisions 0: smooth-shaded body and NURBS leaves, analytic soil
disk). Mitsuba reads the same pot from pot.ply (written by `photon model pot --subdivisions 0`,
triangulated as Photon does, soil removed) plus a disk for the soil. The camera looks slightly
down, keeping the light out of the frame.""")
    room_materials(s)
    s.diffuse("clay", [0.62, 0.33, 0.22])
    s.diffuse("leaf", [0.16, 0.38, 0.12])
    s.diffuse("soil", [0.2, 0.13, 0.08])
    s.diffuse("blue", [0.15, 0.25, 0.7])
    low_camera(s)
    room(s, front=False)
    y = 2.0 - 1e-3
    s.quad([[-0.3, y, -0.3], [0.3, y, -0.3], [0.3, y, 0.3], [-0.3, y, 0.3]], emission=("power", 14.0), light=True)
    s.sphere([-0.55, 0.3, 0.25], 0.3, "white")
    s.sphere([0.6, 0.2, 0.45], 0.2, "blue")
    tables = [
        {"translate": [4.0, -0.1, -0.012]},
        {"rotate": {"axis": [1.0, 0.0, 0.0], "angle": -90.0}},
        {"scale": 0.5, "translate": [0.15, 0.0, -0.35]},
    ]
    toml = [
        "[[shapes]]",
        'type = "pot"',
        "subdivisions = 0",
        "seed = 0",
        'material = "clay"',
        'soil_material = "soil"',
        'leaf_material = "leaf"',
        "transform = " + toml_transform(tables),
    ]
    m = compose(tables)
    soil_c = xform_point(m, [-4.0, 0.1, 0.7453])
    soil_n = [m[i][2] for i in range(3)]
    dm = [[m[i][0] * 0.64, m[i][1] * 0.64, m[i][2] * 0.64, soil_c[i]] for i in range(3)] + [[0, 0, 0, 1.0]]
    xml = (
        '<shape type="ply">\n'
        '    <string name="filename" value="pot.ply"/>\n'
        f'    <transform name="to_world"><matrix value="{xmatrix(m)}"/></transform>\n'
        '    <ref id="clay"/>\n'
        "</shape>\n"
        '<shape type="ply">\n'
        '    <string name="filename" value="leaves.ply"/>\n'
        f'    <transform name="to_world"><matrix value="{xmatrix(m)}"/></transform>\n'
        '    <ref id="leaf"/>\n'
        "</shape>\n"
        '<shape type="disk">\n'
        f'    <!-- the soil: centre (-4, 0.1, 0.7453), radius 0.64, normal +z in pot coordinates -->\n'
        f'    <transform name="to_world"><matrix value="{xmatrix(dm)}"/></transform>\n'
        '    <ref id="soil"/>\n'
        "</shape>"
    )
    assert norm(soil_n) > 0
    s.raw(toml, xml)
    pot_assets(s)
    s.ref_spp = 4096
    return s


def pot_assets(s):
    """pot.ply and leaves.ply from `photon model pot --subdivisions 0 -o pot-export.ply`
    (ASCII, polygons, with normals). Needs PHOTON (the binary) unless the files exist."""
    d = os.path.join(HERE, s.name)
    if os.path.exists(os.path.join(d, "pot.ply")) and os.path.exists(os.path.join(d, "leaves.ply")):
        return
    import subprocess
    import tempfile

    photon = os.environ.get("PHOTON", "photon")
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "pot.ply")
        subprocess.run([photon, "model", "pot", "--subdivisions", "0", "--seed", "0", "-o", src], check=True)
        with open(src) as f:
            lines = f.read().splitlines()
    end = lines.index("end_header")
    nv = int(next(l for l in lines if l.startswith("element vertex")).split()[2])
    nf = int(next(l for l in lines if l.startswith("element face")).split()[2])
    verts = [list(map(float, l.split())) for l in lines[end + 1:end + 1 + nv]]
    faces = [list(map(int, l.split()))[1:] for l in lines[end + 1 + nv:end + 1 + nv + nf]]
    # Parts in order pot, soil, leaves; the soil is the one 32-gon at height 0.7453.
    soil = [i for i, f in enumerate(faces) if len(f) == 32]
    assert len(soil) == 1, soil
    k = soil[0]
    parts = {"pot.ply": faces[:k], "leaves.ply": faces[k + 1:]}
    for fname, fs in parts.items():
        used = sorted({v for f in fs for v in f})
        remap = {v: i for i, v in enumerate(used)}
        tris = [[remap[f[0]], remap[f[j]], remap[f[j + 1]]] for f in fs for j in range(1, len(f) - 1)]
        pos = [verts[v][:3] for v in used]
        nrm = [verts[v][3:6] for v in used]
        s.assets[fname] = ply_binary(pos, tris, nrm)


def glass_caustics():
    s = Scene("glass-caustics", """
Caustics: a glass sphere (ior 1.5) and a water sphere (ior 1.33) on a diffuse floor, a mirror
panel on the right wall, lit by a small spherical area light (radius 0.15, given by its power)
above them. The camera stands in the room's open front looking down, with the light above the
frame (its pixels would otherwise carry a large part of the image's mean). The path-traced
reference converges slowly in the caustics: see README.md for its noise.""")
    room_materials(s)
    s.glass("glass", 1.5)
    s.glass("water", 1.33)
    s.mirror("mirror", 0.9)
    s.set_camera([0.0, 1.3, 1.6], [0.0, 0.35, -0.5], fov=62.0)
    room(s)
    s.quad([[0.99, 0.05, -0.9], [0.99, 0.05, 0.3], [0.99, 0.85, 0.3], [0.99, 0.85, -0.9]], "mirror")
    s.sphere([-0.42, 0.35, -0.35], 0.35, "glass")
    s.sphere([0.42, 0.3, -0.05], 0.3, "water")
    s.sphere([0.0, 1.8, -0.3], 0.15, emission=("power", [30.0, 29.0, 27.0]))
    s.ref_spp = 32768
    return s


def indirect_only():
    s = Scene("indirect-only", """
Indirect light only: an area light 1.3 above the floor faces the ceiling, hidden from the camera
and from everything below it by a white baffle 1 cm under it (a cove light): the box and the
sphere on the floor, the floor and the lower walls are lit only by light bounced off the
ceiling and the upper walls.""")
    room_materials(s)
    s.diffuse("orange", [0.75, 0.45, 0.15])
    std_camera(s)
    room(s)
    s.quad([[-0.6, 1.3, 0.3], [0.6, 1.3, 0.3], [0.6, 1.3, -0.7], [-0.6, 1.3, -0.7]], emission=("radiance", 5.0), light=True)
    s.quad([[-0.65, 1.29, -0.75], [0.65, 1.29, -0.75], [0.65, 1.29, 0.35], [-0.65, 1.29, 0.35]], "white")
    s.box([0.45, 0.7, 0.45], "orange", rotate_y=-20.0, translate=[-0.4, 0.35, -0.3])
    s.sphere([0.4, 0.3, 0.3], 0.3, "white")
    s.ref_spp = 24576
    return s


def textured_mesh():
    s = Scene("textured-mesh", """
Textures and meshes: a floor read from floor.obj with texture coordinates running 0..3 (the
8x8 sRGB PNG repeats, bilinear filtering between texels), a textured quad on the back wall
(the quad's own (u, v)), a textured sphere (its (phi / 2 pi, theta / pi) about +z, the pole
toward the camera), and a flat-shaded torus read from torus.ply (256 triangles, no normals),
under a ceiling area light kept out of the frame.""")
    room_materials(s)
    s.diffuse("tex", texture="tiles8.png")
    s.diffuse("torus", [0.8, 0.75, 0.3])
    low_camera(s)
    room(s, front=False)
    # Replace the floor and the back wall: drop the room's first and third quads.
    del s.shapes[2]
    del s.shapes[0]
    s.quad([[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 2.0, -1.0], [-1.0, 2.0, -1.0]], "tex")
    s.mesh("floor.obj", "tex", [{"translate": [0.0, 0.0, 0.0]}], flat=True)
    s.sphere([-0.6, 0.3, 0.45], 0.3, "tex")
    s.mesh("torus.ply", "torus", [{"scale": 0.5, "rotate": {"axis": [1.0, 0.0, 0.0], "angle": 60.0},
                                   "translate": [0.1, 0.45, 0.0]}], flat=True)
    y = 2.0 - 1e-3
    s.quad([[-0.3, y, -0.3], [0.3, y, -0.3], [0.3, y, 0.3], [-0.3, y, 0.3]], emission=("radiance", 24.0), light=True)
    # 8x8 texture, asymmetric so flips and swaps show: a red L in the top-left, a blue bar at the
    # bottom, a green texel top-right, grey/white checks elsewhere.
    px = []
    for j in range(8):
        row = []
        for i in range(8):
            c = (200, 200, 200) if (i + j) % 2 == 0 else (90, 90, 90)
            if (i == 0 and j < 4) or (j == 3 and i < 3):
                c = (220, 30, 20)
            if j == 7 and 2 <= i <= 6:
                c = (20, 40, 230)
            if j == 0 and i == 7:
                c = (30, 210, 40)
            row.append(c)
        px.append(row)
    s.assets["tiles8.png"] = png_rgb8(8, 8, px)
    s.assets["floor.obj"] = (
        b"# Floor 2 x 2 at y = 0, texture coordinates 0..3 (the texture repeats 3 times).\n"
        b"v -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 0 -1\n"
        b"vt 0 0\nvt 3 0\nvt 3 3\nvt 0 3\n"
        b"f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"
    )
    # Torus: major radius 1, minor 0.35, 16 x 8 quads = 256 triangles, axis +z.
    pos, tris = [], []
    nu, nv = 16, 8
    for i in range(nu):
        a = 2 * math.pi * i / nu
        for j in range(nv):
            b = 2 * math.pi * j / nv
            r = 1.0 + 0.35 * math.cos(b)
            pos.append([r * math.cos(a), r * math.sin(a), 0.35 * math.sin(b)])
    for i in range(nu):
        for j in range(nv):
            p00 = i * nv + j
            p10 = ((i + 1) % nu) * nv + j
            p11 = ((i + 1) % nu) * nv + (j + 1) % nv
            p01 = i * nv + (j + 1) % nv
            tris += [[p00, p10, p11], [p00, p11, p01]]
    s.assets["torus.ply"] = ply_binary(pos, tris)
    s.ref_spp = 3072
    return s


def millimetres():
    s = Scene("millimetres", """
A scene built in millimetres: a 400 mm box room (open at the front) with a 100 mm square
ceiling light 1 mm below the ceiling (out of the frame), two spheres (60 and 45 mm) and a
100 x 160 x 100 mm box.""")
    room_materials(s)
    s.diffuse("blue", [0.15, 0.25, 0.7])
    low_camera(s, scale=200.0)
    room(s, -200.0, 200.0, 0.0, 400.0, -200.0, 200.0)
    y = 399.0
    s.quad([[-50.0, y, -50.0], [50.0, y, -50.0], [50.0, y, 50.0], [-50.0, y, 50.0]], emission=("radiance", 30.0), light=True)
    s.sphere([-90.0, 60.0, 20.0], 60.0, "white")
    s.sphere([100.0, 45.0, 90.0], 45.0, "blue")
    s.box([100.0, 160.0, 100.0], "white", rotate_y=30.0, translate=[70.0, 80.0, -90.0])
    s.ref_spp = 4096
    return s


def light_strip():
    s = Scene("light-strip", """
A Cornell-like box (2 x 2 x 2, red and green side walls) lit by a thin light strip 1.2 x 0.04
(0.6 x 0.02 of the room's width) 3 mm below the ceiling, given by its power and emitting from
both faces, as Blender's glTF export writes emissive meshes (doubleSided): the ceiling beside the
strip is lit hundreds of times more than the room, the kind of export where final gathering
showed speckles. Two boxes stand on the floor. The camera
looks slightly down so that the strip itself is just out of the frame: its pixels, a fraction
of a pixel tall and 80 times brighter than the walls, would otherwise carry half of the image's
mean and make the mean ratio converge slowly.""")
    room_materials(s)
    s.set_camera([0.0, 0.95, 2.9], [0.0, 0.55, 0.0], fov=39.3)
    room(s)
    y = 2.0 - 3e-3
    s.quad([[-0.6, y, -0.02], [0.6, y, -0.02], [0.6, y, 0.02], [-0.6, y, 0.02]], emission=("power", 24.0),
           light=True, two_sided=True)
    s.box([0.55, 0.55, 0.55], "white", rotate_y=-17.0, translate=[0.35, 0.275, 0.3])
    s.box([0.55, 1.2, 0.55], "white", rotate_y=18.0, translate=[-0.35, 0.6, -0.35])
    s.ref_spp = 32768
    return s


def glossy_cornell():
    s = Scene("glossy-cornell", """
Glossy materials under a ceiling quad light (out of the frame) in a Cornell-like box: a rough gold
sphere (conductor, GGX alpha 0.2; Mitsuba roughconductor with its "Au" preset) and a rough glass
sphere (ior 1.5, GGX alpha 0.1; Mitsuba roughdielectric), which casts a blurred caustic. Mitsuba's
microfacet models use the separable Smith G1(wi) G1(wo), not the height-correlated form (see
README.md).""")
    room_materials(s)
    s.conductor("gold", "gold", 0.2)
    s.glass("frosted", 1.5, 0.1)
    low_camera(s)
    room(s)
    y = 2.0 - 1e-3
    s.quad([[-0.3, y, -0.3], [0.3, y, -0.3], [0.3, y, 0.3], [-0.3, y, 0.3]], emission=("power", 14.0), light=True)
    s.sphere([-0.45, 0.38, -0.25], 0.38, "gold")
    s.sphere([0.45, 0.3, 0.2], 0.3, "frosted")
    s.ref_spp = 32768
    return s


def env_spheres():
    s = Scene("env-spheres", """
An environment light only: the procedural sky of make_sky.py (sky.exr, beside this file: a blue
sky, a brown ground half, a soft sun 5-8 degrees in radius at 35 degrees elevation, 60 times
the sky's radiance), turned 30 degrees about +y so that the sun shines from the right (from
(0.81, 0.57, 0.09)), over a large grey diffuse ground plane. Ten glTF metallic-roughness (pbr)
spheres of one base colour: the front row dielectric (metallic 0), the back row metal
(metallic 1), roughness 0, 0.25, 0.5, 0.75, 1 from left to right. Mitsuba renders the pbr
material with the Python plugin gltf_pbr.py. The camera looks down enough to keep the sky and
the plane's far edge out of the frame; the sky is seen in the spheres.""")
    s.diffuse("ground", [0.5, 0.5, 0.5])
    for row, metallic in enumerate([0.0, 1.0]):
        for i, roughness in enumerate([0.0, 0.25, 0.5, 0.75, 1.0]):
            s.pbr(f"pbr{row}{i}", [0.9, 0.5, 0.3], metallic, roughness)
    s.set_camera([0.0, 2.2, 2.6], [0.0, 0.1, -0.1], fov=47.0)
    # The ground: 20 x 20, large enough to fill the frame (its far edge, 10 degrees below the
    # horizon, is 4 degrees above the frame's top), small enough that photons leaving a disc over
    # the scene's bounding sphere (radius 14) still land near the spheres.
    g = 10.0
    s.quad([[-g, 0.0, g], [g, 0.0, g], [g, 0.0, -g], [-g, 0.0, -g]], "ground")
    for row, z in enumerate([0.35, -0.35]):
        for i in range(5):
            s.sphere([-1.0 + 0.5 * i, 0.22, z], 0.22, f"pbr{row}{i}")
    s.environment(file="sky.exr", intensity=1.0, rotate=30.0)
    sky = os.path.join(ROOT, "scenes", "assets", "sky.exr")
    if not os.path.exists(sky):
        raise SystemExit("scenes/assets/sky.exr is missing: run python validation/make_sky.py (numpy, mitsuba)")
    with open(sky, "rb") as f:
        s.assets["sky.exr"] = f.read()
    s.ref_spp = 8192
    return s


def glossy_floor_spot():
    s = Scene("glossy-floor-spot", """
A glossy floor (pbr: grey base colour 0.5, metallic 0, roughness 0.4, GGX alpha 0.16) in a
Cornell-like box, lit by a hard-edged spot light low by the back wall aimed down toward the
front: the light's glossy highlight lies on the floor in front of a diffuse box and sphere,
whose shadows fall toward the camera; the walls are seen blurred in the floor. Mitsuba renders
the pbr material with the Python plugin gltf_pbr.py.""")
    room_materials(s)
    s.pbr("floor", [0.5, 0.5, 0.5], 0.0, 0.4)
    s.diffuse("blue", [0.15, 0.25, 0.7])
    s.diffuse("yellow", [0.7, 0.6, 0.2])
    s.set_camera([0.0, 1.6, 2.6], [0.0, 0.3, -0.1], fov=39.3)
    room(s)
    # The room's floor, replaced by the glossy one, 0.3 longer in front (the frame's bottom edge).
    del s.shapes[0]
    s.quad([[-1.0, 0.0, 1.3], [1.0, 0.0, 1.3], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]], "floor")
    s.box([0.45, 0.6, 0.45], "blue", rotate_y=25.0, translate=[-0.45, 0.3, -0.35])
    s.sphere([0.45, 0.25, -0.3], 0.25, "yellow")
    s.spot([0.2, 1.25, -0.9], [0.05, 0.0, 0.45], [10.0, 9.5, 8.8], 35.0)
    s.ref_spp = 12288
    return s


# --------------------------------------------------------------------------------------------
# Participating media (Mitsuba: integrator volpath)


def closed_room_camera(s, fov=62.0, look_y=0.85):
    """For scenes filled with a medium: the room is closed (front wall too) and the camera stands
    inside it, 2 cm from the front wall, so that no path leaves into endless fog."""
    s.set_camera([0.0, 1.0, 0.98], [0.0, look_y, -1.0], fov=fov)


def fog_spot():
    s = Scene("fog-spot", """
Fog filling a closed room (the scene's medium: Photon's top-level `medium`, Mitsuba's sensor
medium; the camera stands inside, by the front wall): sigma_s 0.4, sigma_a 0.03 per unit,
Henyey-Greenstein g 0.3. A hard-edged spot light (30 degrees) high by the left wall, aimed down
across the room at a yellow sphere on the floor, draws a visible beam (single scattering) with
the sphere's shadow in it; the rest of the room and the fog are lit by light scattered by the
fog and the walls. The spot light sits in the fog.""")
    room_materials(s)
    s.diffuse("yellow", [0.7, 0.6, 0.2])
    s.define_medium("fog", sigma_a=[0.03, 0.03, 0.03], sigma_s=[0.3, 0.3, 0.3], g=0.3)
    s.set_medium("fog")
    closed_room_camera(s, fov=55.0, look_y=0.7)
    room(s, front=True)
    s.sphere([0.3, 0.3, -0.5], 0.3, "yellow")
    s.spot([-0.85, 1.75, -0.25], [0.45, 0.0, -0.6], [14.0, 13.0, 11.0], 25.0)
    s.ref_spp = 8192
    return s


def coloured_fog():
    s = Scene("coloured-fog", """
Fog whose scattering depends on the colour, filling a closed room (the scene's medium; the camera
stands inside, by the front wall): sigma_s 0.4 0.9 1.6 per unit (blue scatters four times as much
as red, as in haze), sigma_a 0.05 0.1 0.05, Henyey-Greenstein g 0.3. A small sphere light (radius
0.06, given by its power) hangs in the fog above a white sphere on the floor, just above the
frame. Each colour takes its own free paths: blue light is scattered many times before it
reaches a wall, red mostly crosses the room. Distances are drawn for one channel and weighed
for the others (spectral MIS), here on every scattering event. The reference is Mitsuba's
`volpathmis`, which weighs the channels so too: `volpath` divides by the drawn channel's density
alone, so a path whose distances were drawn for red multiplies blue's weight by up to 3.6 at each
scattering event, and its blue read 1% low at 8192 spp.""")
    room_materials(s)
    s.define_medium("haze", sigma_a=[0.05, 0.1, 0.05], sigma_s=[0.4, 0.9, 1.6], g=0.3)
    s.set_medium("haze")
    closed_room_camera(s, fov=55.0, look_y=0.7)
    room(s, front=True)
    s.sphere([0.25, 0.3, -0.45], 0.3, "white")
    s.sphere([-0.3, 1.75, -0.3], 0.06, emission=("power", [30.0, 30.0, 30.0]))
    s.integrator = "volpathmis"
    s.ref_spp = 8192
    return s


def fog_box():
    s = Scene("fog-box", """
A box of fog in a room in vacuum (open at the front) under a ceiling quad light (out of the
frame): the box (0.9 x 0.95 x 0.9, its bottom face 1 cm under the floor, so the floor cuts it)
is an invisible boundary (no material; Mitsuba: null BSDF) around a forward-scattering medium
(sigma_s 2.2, sigma_a 0.05 0.12 0.25 per unit: a warm, channel-dependent extinction; g 0.6). A
white sphere stands on the floor inside it, a blue one outside beside it. Light enters and
leaves through the box's faces; the sphere and the box cast shadows through the fog.""")
    room_materials(s)
    s.diffuse("blue", [0.15, 0.25, 0.7])
    s.define_medium("haze", sigma_a=[0.05, 0.12, 0.25], sigma_s=[2.2, 2.2, 2.2], g=0.6)
    low_camera(s)
    room(s)
    y = 2.0 - 1e-3
    s.quad([[-0.3, y, -0.3], [0.3, y, -0.3], [0.3, y, 0.3], [-0.3, y, 0.3]], emission=("power", 16.0), light=True)
    s.box([0.9, 0.95, 0.9], None, translate=[-0.3, 0.465, -0.25], interior="haze")
    s.sphere([-0.3, 0.25, -0.25], 0.25, "white")
    s.sphere([0.55, 0.25, 0.25], 0.25, "blue")
    s.ref_spp = 6144
    return s


def absorbing_water():
    s = Scene("absorbing-water", """
A block of water: a glass box (ior 1.33; Mitsuba dielectric, int_ior 1.33, ext_ior 1) 0.8 x 0.6 x
0.5, turned 25 degrees, standing 2 mm above the floor, around an interior medium that absorbs red
most (sigma_a 0.9 0.25 0.1 per unit) and scatters a little (sigma_s 0.3, isotropic): a blue-green
tint growing with the path length, a faint glow of light scattered inside, the room refracted
through it. A yellow sphere stands behind it. Lit by a 1 x 1 ceiling panel 10 cm below the ceiling
(out of the frame), large so that paths scattered in the water find it through the glass (shadow
rays do not pass the glass). The floor reaches 0.4 beyond the room's open front, under the
frame's bottom edge.""")
    room_materials(s)
    s.diffuse("yellow", [0.7, 0.6, 0.2])
    s.glass("water-glass", 1.33)
    s.define_medium("water", sigma_a=[0.9, 0.25, 0.1], sigma_s=[0.3, 0.3, 0.3], g=0.0)
    s.set_camera([0.0, 0.95, 2.9], [0.0, 0.55, 0.0], fov=39.3)
    room(s)
    # The room's floor, 0.4 longer in front: the frame's bottom edge sees past z = 1.
    del s.shapes[0]
    s.quad([[-1.0, 0.0, 1.4], [1.0, 0.0, 1.4], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]], "white")
    y = 1.9
    s.quad([[-0.5, y, -0.5], [0.5, y, -0.5], [0.5, y, 0.5], [-0.5, y, 0.5]], emission=("radiance", 4.0), light=True)
    s.box([0.8, 0.6, 0.5], "water-glass", rotate_y=25.0, translate=[-0.15, 0.302, 0.05], interior="water")
    s.sphere([0.45, 0.25, -0.5], 0.25, "yellow")
    s.ref_spp = 12288
    return s


def thick_medium():
    s = Scene("thick-medium", """
A dense, bright medium: an invisible sphere (radius 0.4, no material; Mitsuba: null BSDF) 1 cm
above the floor holding a medium given in Mitsuba's form, albedo 0.98 and density 9 per unit
(sigma_s 8.82, sigma_a 0.18, isotropic): optical radius 3.6, a cloud-like ball lit by a ceiling
quad light (out of the frame), with many scattering events per path. A blue sphere beside it.""")
    room_materials(s)
    s.diffuse("blue", [0.15, 0.25, 0.7])
    s.define_medium("cloud", albedo=0.98, density=9.0, g=0.0)
    low_camera(s)
    room(s)
    y = 2.0 - 1e-3
    s.quad([[-0.3, y, -0.3], [0.3, y, -0.3], [0.3, y, 0.3], [-0.3, y, 0.3]], emission=("power", 14.0), light=True)
    s.sphere([-0.2, 0.41, -0.2], 0.4, None, interior="cloud")
    s.sphere([0.6, 0.2, 0.35], 0.2, "blue")
    s.ref_spp = 6144
    return s


# The density grid of tests/fixtures/vdb/smoke_blosc_half_f24.vdb, as vdb_to_vol.py prints it:
# 26 x 17 x 36 active voxels from index (5, 11, 2), UniformScaleMap of voxel size 0.05 (float32
# 0.05 in the file: 7e-10 more, i.e. Photon's cube is 1e-8 larger in relative terms: nothing).
SMOKE_VDB = os.path.join(ROOT, "tests", "fixtures", "vdb", "smoke_blosc_half_f24.vdb")
SMOKE_RES = (26, 17, 36)
SMOKE_INDEX_MIN = (5, 11, 2)
SMOKE_VOXEL = 0.05


def smoke_grid():
    s = Scene("smoke-grid", """
A heterogeneous medium on a voxel grid: a smoke plume (tests/fixtures/vdb/smoke_blosc_half_f24.vdb,
written with Blender 4.5's cache writer: grid "density", 26 x 17 x 36 active voxels of 0.05,
half floats, Blosc; values up to 0.995, mean 0.086) standing on the floor under a ceiling quad
light (out of the frame), a blue sphere beside it. Photon reads smoke.vdb (`grid`), Mitsuba
smoke.vol, the same dense box over the active voxels written by vdb_to_vol.py (`heterogeneous`
medium, `gridvolume` sigma_t): both fill the grid's unit cube, trilinear between voxel centres.
The file's z-up cube (1.3 x 0.85 x 1.8 in its world) is scaled by 0.44, turned -90 degrees about
x (z up -> y up) and moved so that it stands 1 cm above the floor: 0.572 x 0.792 x 0.374. An
invisible box (no material; Mitsuba: null BSDF) coincides with the cube and bounds the medium, so
neither renderer looks outside the cube. Albedo 0.92 0.9 0.86 (a warm grey), density scale 20
per unit (sigma_t = 20 x grid value): optical depth up to about 4 across the plume's trunk, 11
down its length; Henyey-Greenstein g 0.3.""")
    room_materials(s)
    s.diffuse("blue", [0.15, 0.25, 0.7])
    nx, ny, nz = SMOKE_RES
    file_placement = [
        [nx * SMOKE_VOXEL, 0.0, 0.0, (SMOKE_INDEX_MIN[0] - 0.5) * SMOKE_VOXEL],
        [0.0, ny * SMOKE_VOXEL, 0.0, (SMOKE_INDEX_MIN[1] - 0.5) * SMOKE_VOXEL],
        [0.0, 0.0, nz * SMOKE_VOXEL, (SMOKE_INDEX_MIN[2] - 0.5) * SMOKE_VOXEL],
        [0.0, 0.0, 0.0, 1.0],
    ]
    # Scaled and turned z-up to y-up; then moved so that the cube's lowest corner lands at
    # (-0.536, 0.01, -0.187): centred on x = -0.25, z = 0, its bottom 1 cm above the floor.
    turn = {"scale": 0.44, "rotate": {"axis": [1.0, 0.0, 0.0], "angle": -90.0}}
    lo, _ = Grid("", "", [turn], file_placement).world_box()
    translate = [round(t - l, 9) for t, l in zip([-0.536, 0.01, -0.187], lo)]
    grid = Grid("smoke.vdb", "smoke.vol", [dict(turn, translate=translate)], file_placement)
    s.define_medium("smoke", albedo=[0.92, 0.9, 0.86], density=20.0, g=0.3, grid=grid)
    low_camera(s)
    room(s)
    y = 2.0 - 1e-3
    s.quad([[-0.3, y, -0.3], [0.3, y, -0.3], [0.3, y, 0.3], [-0.3, y, 0.3]], emission=("power", 14.0), light=True)
    lo, hi = grid.world_box()
    size = [round(h - l, 9) for l, h in zip(lo, hi)]
    centre = [round((l + h) / 2, 9) + 0.0 for l, h in zip(lo, hi)]  # + 0.0: no "-0.0"
    s.box(size, None, translate=centre, interior="smoke")
    s.sphere([0.45, 0.2, 0.15], 0.2, "blue")
    smoke_assets(s)
    s.ref_spp = 6144
    return s


def smoke_assets(s):
    """smoke.vdb (the test fixture) and smoke.vol (vdb_to_vol.py, which needs bpy: run with the
    Python of $BPY_PYTHON, default this one, unless the file exists)."""
    with open(SMOKE_VDB, "rb") as f:
        s.assets["smoke.vdb"] = f.read()
    vol = os.path.join(HERE, s.name, "smoke.vol")
    if not os.path.exists(vol):
        import subprocess

        os.makedirs(os.path.dirname(vol), exist_ok=True)
        python = os.environ.get("BPY_PYTHON", sys.executable)
        subprocess.run([python, os.path.join(HERE, "vdb_to_vol.py"), SMOKE_VDB, vol], check=True)
    with open(vol, "rb") as f:
        head = f.read(48)
    dims = struct.unpack("<3i", head[8:20])
    assert head[:4] == b"VOL\x03" and dims == SMOKE_RES, (vol, head[:4], dims)


def volumetric_caustic():
    s = Scene("volumetric-caustic", """
A volumetric caustic, for an equal-time study rather than a unit test: thin fog fills a closed,
dim room (the scene's medium: sigma_s 0.2, sigma_a 0.01, g 0.2; grey walls 0.3, floor 0.4). A
small quad light (0.15 x 0.15, power 60, facing down, 5 cm under the ceiling) inside a dark
square shade (four quads 0.18 wide, from 1 cm under the ceiling down to y = 1.5) shines on a
glass sphere (ior 1.5, radius 0.25, centre 0.95 below the light): the sphere focuses the light
into a beam that narrows to a focus about 0.6 under the sphere's centre and widens again down to
the floor, where the caustic lies in the sphere's shadow, ringed by the light that passes beside
the sphere. The sphere's inside is clear: `interior = "air"` (a medium of zero coefficients;
Mitsuba: no interior medium, vacuum) and `exterior = "fog"`. The camera stands in the room by
the front wall, the shade and the light just above the frame. A path tracer finds the beam only
when a scattering point's sampled direction passes through the sphere to the small light (shadow
rays stop at the glass): the reference is far from converged there; see README.md.""")
    s.diffuse("grey", [0.3, 0.3, 0.3])
    s.diffuse("floor", [0.4, 0.4, 0.4])
    s.diffuse("shade", [0.05, 0.05, 0.05])
    s.glass("glass", 1.5)
    s.define_medium("fog", sigma_a=[0.01, 0.01, 0.01], sigma_s=[0.2, 0.2, 0.2], g=0.2)
    s.define_medium("air", sigma_a=0.0, sigma_s=0.0)
    s.set_medium("fog")
    s.set_camera([0.0, 1.0, 0.98], [0.0, 0.65, -1.0], fov=60.0)
    room(s, left="grey", right="grey", walls="grey", front=True)
    del s.shapes[0]  # the room's floor, replaced by a lighter one
    s.quad([[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 0.0, -1.0]], "floor")
    cx, cz = 0.0, -0.3
    h, y = 0.075, 1.95
    s.quad([[cx - h, y, cz - h], [cx + h, y, cz - h], [cx + h, y, cz + h], [cx - h, y, cz + h]],
           emission=("power", 60.0), light=True)
    w, y0, y1 = 0.09, 1.5, 1.99
    corners = [[cx - w, cz - w], [cx + w, cz - w], [cx + w, cz + w], [cx - w, cz + w]]
    for k in range(4):
        (xa, za), (xb, zb) = corners[k], corners[(k + 1) % 4]
        s.quad([[xa, y0, za], [xb, y0, zb], [xb, y1, zb], [xa, y1, za]], "shade")
    s.sphere([cx, 1.0, cz], 0.25, "glass", interior="air", exterior="fog")
    s.ref_spp = 20480
    s.reference_file = "study-reference.exr"
    return s


# --------------------------------------------------------------------------------------------
# Light paths that favour one technique each (vertex connection and merging, `--integrator vcm`):
# a caustic seen only in a mirror (merging), a lamp in a shade and a door ajar (connecting light
# subpaths). Hard for a path tracer: their references need many samples (README.md).


def prism(s, centre, apothem, y0, y1, material, sides=8):
    """An open-ended vertical prism of `sides` quads (a lamp shade or a can) around the vertical
    line through `centre` (x, z), from y0 to y1: no top, no bottom. Each quad's front faces out."""
    cx, cz = centre
    r = apothem / math.cos(math.pi / sides)  # to the corners
    for k in range(sides):
        a0 = 2 * math.pi * (k - 0.5) / sides
        a1 = 2 * math.pi * (k + 0.5) / sides
        p0 = [cx + r * math.cos(a0), cz + r * math.sin(a0)]
        p1 = [cx + r * math.cos(a1), cz + r * math.sin(a1)]
        s.quad([[p1[0], y0, p1[1]], [p0[0], y0, p0[1]], [p0[0], y1, p0[1]], [p1[0], y1, p1[1]]], material)


def mirror_caustic():
    s = Scene("mirror-caustic", """
A caustic seen only in a mirror (specular-diffuse-specular light): a closed room, the camera
inside by the front wall looking at a mirror (reflectance 0.8) on the back wall that fills much
of the frame. Behind and below the camera, out of its direct view, a glass sphere (ior 1.5)
hangs above the floor under a small two-sided quad light (0.4 x 0.4, its own material white):
the sphere focuses the light into a caustic on the floor inside its shadow, and the camera sees
floor, caustic and sphere only in the mirror (the light itself is above the mirror's view).
The light also shines on the mirror, which throws it back on the floor around the sphere: light
the camera sees in the mirror after a diffuse bounce between two mirror reflections,
specular-diffuse-specular again. The light's top face lights the ceiling. A path tracer finds both only when a
diffuse bounce from the floor, seen in the mirror, happens to reach the light through the glass
or the mirror; a light tracer cannot connect the floor to the camera through the mirror. (A
smaller light, kept off the mirror in a black can, left the reference far from converged.)""")
    room_materials(s)
    s.mirror("mirror", 0.8)
    s.glass("glass", 1.5)
    s.set_camera([0.0, 1.25, 0.95], [0.0, 1.1, -1.0], fov=50.0)
    room(s, front=True)
    s.quad([[-0.7, 0.35, -0.99], [0.7, 0.35, -0.99], [0.7, 1.45, -0.99], [-0.7, 1.45, -0.99]], "mirror")
    cx, cz = 0.0, 0.6
    s.sphere([cx, 0.7, cz], 0.25, "glass")
    h, y = 0.2, 1.7
    s.quad([[cx - h, y, cz - h], [cx + h, y, cz - h], [cx + h, y, cz + h], [cx - h, y, cz + h]],
           "white", emission=("power", 20.0), light=True, two_sided=True)
    s.ref_spp = 90112
    return s


def lamp_shade():
    s = Scene("lamp-shade", """
A light inside a lamp shade: a bulb (an emitting sphere, radius 0.07, its own material white) at
the centre of an open-ended octagonal shade (a diffuse two-sided prism, 0.7 across, 0.4 tall,
warm) hanging in the middle of a Cornell-like room (open at the front): about half of the bulb's
light leaves straight through the shade's two openings (a pool of light on the floor, another on
the ceiling), the rest after bouncing inside the shade. The camera, below the shade, sees its
outside and a strip of its lit inside, not the bulb. For a path tracer the light bounced inside
the shade is found only when a diffuse bounce from the room enters an opening (a narrower,
taller shade left the reference far from converged).""")
    room_materials(s)
    s.diffuse("shade", [0.7, 0.6, 0.4])
    s.diffuse("blue", [0.15, 0.25, 0.7])
    std_camera(s)
    room(s)
    prism(s, (0.0, 0.0), 0.35, 1.25, 1.65, "shade")
    s.sphere([0.0, 1.45, 0.0], 0.07, "white", emission=("power", 30.0))
    s.box([0.5, 0.8, 0.5], "white", rotate_y=20.0, translate=[-0.45, 0.4, -0.35])
    s.sphere([0.45, 0.3, 0.15], 0.3, "blue")
    s.ref_spp = 81920
    return s


def door_ajar():
    s = Scene("door-ajar", """
Veach's door ajar: two closed rooms (each 2 x 2 x 2) share a wall with a doorway (0.6 x 1.6)
whose door (a box 0.6 wide, 4 cm thick, reaching 10 cm above the doorway behind the lintel and
through the floor) stands open 40 degrees into the far room, hinged at the doorway's right edge.
The only light, a two-sided vertical quad light (0.3 x 0.3, facing the side walls, its own
material white), stands in the far room left of the door: the near room is lit only through the
wedge-shaped gap between the door's free edge and the doorway, by a beam on its right wall and
floor and by light bounced in the far room. The camera, in the near room's front left corner,
looks at the door and the lit wall. (Opened 10 to 30 degrees, the path-traced reference needed
far more than 100 000 samples per pixel.)""")
    room_materials(s)
    s.diffuse("door", [0.6, 0.45, 0.3])
    s.set_camera([-0.75, 1.1, 0.9], [0.6, 0.6, -0.7], fov=60.0)
    z0, zw, z1 = -3.0, -1.0, 1.0  # far room's back wall, the dividing wall, near room's front wall
    room(s, z0=z0, z1=z1, front=True)
    xa, xb, top = 0.15, 0.75, 1.6  # the doorway
    # The dividing wall around the doorway.
    s.quad([[-1.0, 0.0, zw], [xa, 0.0, zw], [xa, 2.0, zw], [-1.0, 2.0, zw]], "white")
    s.quad([[xb, 0.0, zw], [1.0, 0.0, zw], [1.0, 2.0, zw], [xb, 2.0, zw]], "white")
    s.quad([[xa, top, zw], [xb, top, zw], [xb, 2.0, zw], [xa, 2.0, zw]], "white")
    # The door: its near face's hinge-side edge stays on the hinge (xb, zw); turned by -angle
    # about +y, its free edge swings into the far room.
    angle, w, t = 40.0, xb - xa, 0.04
    size = [w, top + 0.1 + 0.01, t]
    c, sn = math.cos(math.radians(-angle)), math.sin(math.radians(-angle))
    corner = [w / 2, t / 2]  # the near face's hinge-side edge, from the box's centre (x, z)
    centre = [round(xb - (c * corner[0] + sn * corner[1]), 9),
              round((top + 0.1 - 0.01) / 2, 9),
              round(zw - (-sn * corner[0] + c * corner[1]), 9)]
    s.box(size, "door", rotate_y=-angle, translate=centre)
    h, lx, ly, lz = 0.15, -0.6, 1.0, -2.0
    s.quad([[lx, ly - h, lz + h], [lx, ly - h, lz - h], [lx, ly + h, lz - h], [lx, ly + h, lz + h]],
           "white", emission=("power", 70.0), light=True, two_sided=True)
    s.ref_spp = 106496
    return s


SCENES = {
    f.__name__.replace("_", "-"): f
    for f in [point_light, spot_light, directional, grazing_area, curved_ceiling, glass_caustics,
              indirect_only, textured_mesh, millimetres, light_strip, glossy_cornell, env_spheres,
              glossy_floor_spot, fog_spot, coloured_fog, fog_box, absorbing_water, thick_medium, volumetric_caustic,
              smoke_grid, mirror_caustic, lamp_shade, door_ajar]
}


def main(names):
    for name in names or SCENES:
        s = SCENES[name]()
        s.write()
        print(f"wrote validation/{name}/")


if __name__ == "__main__":
    main(sys.argv[1:])
