"""Writes scenes/prism.toml, scenes/prism-fog.toml and scenes/gem.toml, the spectral showcase: `python3 scenes/spectral_scenes.py scenes` (standard library only). The prism is the geometry of tests/spectral.rs."""
import math, sys

def norm(v):
    l = math.sqrt(sum(c*c for c in v)); return [c/l for c in v]
def add(a,b): return [x+y for x,y in zip(a,b)]
def sub(a,b): return [x-y for x,y in zip(a,b)]
def mul(a,k): return [x*k for x in a]
def dot(a,b): return sum(x*y for x,y in zip(a,b))
def cross(a,b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def f(v): return "[" + ", ".join(f"{x:.5g}" for x in v) + "]"

# SF11 Sellmeier
B=[1.7375969, 0.31374735, 1.898781]; C=[0.013188707, 0.062306814, 155.23629]
def n(l):
    l2=(l/1000)**2; return math.sqrt(1+sum(b*l2/(l2-c) for b,c in zip(B,C)))
def snell(d, nn, eta):
    ci=-dot(d,nn); s2=eta*eta*(1-ci*ci); return norm(add(mul(d,eta), mul(nn, eta*ci-math.sqrt(1-s2))))

BL=[-0.3,0,0]; BR=[0.3,0,0]; AP=[0,0,0.5196152]
def v(p,y): return [p[0], y, p[2]]
along=norm(sub(AP,BL)); normal=[-along[2],0,along[0]]
t=math.radians(60); d=norm(add(mul(normal,-math.cos(t)), mul(along, math.sin(t))))
entry=mul(add(BL,AP),0.5)
def exit_ray(l):
    inside=snell(d, normal, 1/n(l))
    a2=norm(sub(BR,AP)); rn=[-a2[2],0,a2[0]]
    tt=dot(sub(AP,entry),rn)/dot(inside,rn); ex=add(entry, mul(inside,tt))
    return ex, snell(inside, mul(rn,-1), n(l))
ex,out=exit_ray(550)
centre=add(ex, mul(out, 1.5))
right=norm(cross(out,[0,1,0]))
# The prism stands on a floor at y = -0.5, a wall (the screen) across the rainbow.
wall=[add(add(centre, mul(right,s)), [0,tt,0]) for s,tt in [(-1.2,-0.5),(1.2,-0.5),(1.2,1.0),(-1.2,1.0)]]
# Raise everything so the beam runs at y = 0.
light=sub(entry, mul(d,3.0))
cam=add(add(ex, mul(out, -1.1)), add([0, 0.75, 0], mul(right, 0.45)))
look=add(centre, [0, -0.1, 0])
prism=f"""# A prism of N-SF11 (a dense flint glass) throws the rainbow of a narrow white beam on a wall.
# Spectral rendering only: in RGB the beam stays white.
#   photon render scenes/prism.toml --spectral --integrator sppm --time 60 -o prism.png
# Written by scenes/spectral_scenes.py.

[camera]
position = {f(cam)}
look_at = {f(look)}
up = [0.0, 1.0, 0.0]
fov = 42

[render]
width = 480
height = 320
integrator = "sppm"
spectral = true
radius = 0.004

[materials.prism]
type = "glass"
glass = "sf11"

[materials.wall]
type = "diffuse"
albedo = 0.8

[materials.floor]
type = "diffuse"
albedo = 0.25

[[shapes]]
type = "triangles"
material = "prism"
positions = [{f(v(BL,-0.5))}, {f(v(BR,-0.5))}, {f(v(AP,-0.5))},
             {f(v(BL,0.5))}, {f(v(BR,0.5))}, {f(v(AP,0.5))}]
indices = [[0, 1, 2], [3, 5, 4], [0, 4, 1], [0, 3, 4], [1, 5, 2], [1, 4, 5],
           [2, 3, 0], [2, 5, 3]]

[[shapes]]
type = "quad"
material = "wall"
vertices = [{f(wall[0])}, {f(wall[1])}, {f(wall[2])}, {f(wall[3])}]

[[shapes]]
type = "quad"
material = "floor"
vertices = [[-4.0, -0.5, -4.0], [-4.0, -0.5, 4.0], [4.0, -0.5, 4.0], [4.0, -0.5, -4.0]]

[[lights]]
type = "spot"
position = {f(light)}
look_at = {f(entry)}
power = 2.0
angle = 0.25
falloff = 0.05

[[lights]]
type = "environment"
radiance = 0.04
"""
open(sys.argv[1] + "/prism.toml","w").write(prism)

# The same prism in a slab of haze holding the beam's plane (an invisible box; the camera looks
# in from above it), lit by the spot alone.
fog = prism.replace("""# A prism of N-SF11 (a dense flint glass) throws the rainbow of a narrow white beam on a wall.
# Spectral rendering only: in RGB the beam stays white.
#   photon render scenes/prism.toml --spectral --integrator sppm --time 60 -o prism.png""", """# The prism of prism.toml in a slab of haze that holds the beam's plane: the white beam and the
# rainbow it fans into show in the air, as well as on the wall. Spectral rendering only: in RGB
# the beam stays white.
#   photon render scenes/prism-fog.toml --spectral --integrator sppm --time 120 -o prism-fog.png""")
fog = fog.replace("[materials.prism]", """[media.haze]
sigma_a = 0.01
sigma_s = 0.4
g = 0.4

[materials.prism]""")
fog = fog.replace('material = "prism"\npositions', 'material = "prism"\nexterior = "haze"\npositions')
fog = fog[:fog.index('[[lights]]\ntype = "environment"')].rstrip() + """

[[shapes]]                  # no material: an invisible box holding the haze
type = "box"
min = [-3.0, -0.499, -1.8]
max = [2.3, 0.6, 0.7]
interior = "haze"
"""
open(sys.argv[1] + "/prism-fog.toml","w").write(fog)

# A round brilliant: table, crown, girdle, pavilion to a culet; 8-fold, as in a jeweller's cut.
k = 16
r = 0.5
crown_h, pav_h, table_r = 0.16, 0.43, 0.55 * r
pos = [[0, crown_h, 0]]                      # table centre
for i in range(k):
    a = 2*math.pi*i/k
    pos.append([table_r*math.cos(a), crown_h, table_r*math.sin(a)])    # 1..k: table edge
for i in range(k):
    a = 2*math.pi*(i+0.5)/k
    pos.append([r*math.cos(a), 0.0, r*math.sin(a)])                     # k+1..2k: girdle
pos.append([0, -pav_h, 0])                   # culet: 2k+1
tri = []
for i in range(k):
    j = (i+1) % k
    t0, t1 = 1+i, 1+j
    g0, g1 = 1+k+i, 1+k+((i-1) % k)
    tri.append([0, t1, t0])                  # table (normal up)
    tri.append([t0, t1, 1+k+i])              # crown: a facet from the table's edge
    tri.append([1+k+((i-1) % k), t0, 1+k+i]) # crown: a facet from the girdle
    tri.append([1+k+i, 1+k+((i+1) % k), 2*k+1])  # pavilion
# Fix orientation: every face normal must point away from the centre (0, 0, 0).
cen=[0,0,0]
fixed=[]
for a,b,c in tri:
    pa,pb,pc=pos[a],pos[b],pos[c]
    nn=cross(sub(pb,pa),sub(pc,pa)); m=mul(add(add(pa,pb),pc),1/3)
    fixed.append([a,b,c] if dot(nn, sub(m,cen))>0 else [a,c,b])
# Deduplicate the crown (the bezel overlaps the star facets of the simple scheme): keep the
# star and the girdle-bezel triangles that tile the crown ring.
gem_pos = ", ".join(f([p[0], p[1]+pav_h, p[2]]) for p in pos)  # the culet on the floor
gem_idx = ", ".join(str(t) for t in fixed if True)
gem=f"""# A dispersive diamond under a spot light: the fire it throws on the floor.
#   photon render scenes/gem.toml --spectral --integrator sppm --time 60 -o gem.png
# Written by scenes/spectral_scenes.py.

[camera]
position = [1.6, 1.3, 1.9]
look_at = [0.15, 0.1, 0.2]
up = [0.0, 1.0, 0.0]
fov = 38

[render]
width = 400
height = 300
integrator = "sppm"
spectral = true

[materials.diamond]
type = "glass"
glass = "diamond"

[materials.floor]
type = "diffuse"
albedo = 0.6

[[shapes]]
type = "triangles"
material = "diamond"
positions = [{gem_pos}]
indices = [{gem_idx}]

[[shapes]]
type = "quad"
material = "floor"
vertices = [[-5.0, 0.0, -5.0], [-5.0, 0.0, 5.0], [5.0, 0.0, 5.0], [5.0, 0.0, -5.0]]

[[lights]]
type = "spot"
position = [-0.6, 3.0, -0.4]
look_at = [0.0, 0.3, 0.0]
power = 30.0
angle = 8.0
falloff = 1.0

[[lights]]
type = "environment"
radiance = 0.02
"""
open(sys.argv[1] + "/gem.toml","w").write(gem)
