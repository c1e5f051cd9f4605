#!/usr/bin/env python3
"""Writes sphere_light.obj/.mtl: an emissive icosphere replacing the caustics scene's spot.

Radius 1.5 cm at (0, 1.5, 0) (the spot's position), icosahedron subdivided 3 times
(642 vertices, 1280 triangles, outward CCW faces, flat-faceted: no normals are written so
the loader computes them). The emitted radiance Le is chosen so that the sphere's mean
radiant intensity equals the spot's I = 100 W / (2π(1 − cos 25°)) = 169.87 W/sr, i.e. the
flux sent into the spot's 25° cone is the spot's 100 W: a convex Lambertian emitter of area
A emits Φ = π·Le·A in total and I = Φ/(4π) = Le·A/4 on average, so Le = 4·I/A with A the
area of the tessellated mesh. Total flux is then 4π·I = 2134.6 W (see README.md for why
we match the cone's flux rather than the total).
"""
import math

R, C, SUBDIV = 0.015, (0.0, 1.5, 0.0), 3
t = (1 + 5 ** 0.5) / 2
verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
         (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
for _ in range(SUBDIV):
    cache, nf = {}, []
    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in cache:
            m = [(verts[a][i] + verts[b][i]) / 2 for i in range(3)]
            n = math.sqrt(sum(x * x for x in m))
            verts.append(tuple(x / n for x in m))
            cache[key] = len(verts) - 1
        return cache[key]
    for a, b, c in faces:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    faces = nf
pos = [tuple(C[i] + R * v[i] for i in range(3)) for v in verts]
area = 0.0
for a, b, c in faces:
    u = [pos[b][i] - pos[a][i] for i in range(3)]
    w = [pos[c][i] - pos[a][i] for i in range(3)]
    cr = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    # Outward winding: the normal points away from the centre.
    cen = [(pos[a][i] + pos[b][i] + pos[c][i]) / 3 - C[i] for i in range(3)]
    assert sum(cr[i] * cen[i] for i in range(3)) > 0
    area += 0.5 * math.sqrt(sum(x * x for x in cr))
I = 100.0 / (2 * math.pi * (1 - math.cos(math.radians(25))))
Le = 4 * I / area
with open("sphere_light.obj", "w") as f:
    f.write("# Emissive icosphere for caustics-sphere-light (written by make_sphere_light.py)\n")
    f.write(f"# r = {R} m, centre {C}, {len(faces)} triangles, area {area:.6e} m^2, Le = {Le:.6e} W/(sr m^2)\n")
    f.write("mtllib sphere_light.mtl\no sphere_light\n")
    for p in pos:
        f.write("v %.7f %.7f %.7f\n" % p)
    f.write("usemtl sphere_light_emitter\n")
    for a, b, c in faces:
        f.write(f"f {a + 1} {b + 1} {c + 1}\n")
with open("sphere_light.mtl", "w") as f:
    f.write("# Le chosen so the mean intensity equals the spot's 169.87 W/sr (make_sphere_light.py)\n")
    f.write(f"newmtl sphere_light_emitter\nKd 0 0 0\nKe {Le:.6f} {Le:.6f} {Le:.6f}\nillum 1\n")
print(f"area {area:.6e} (sphere {4 * math.pi * R * R:.6e}), I {I:.4f} W/sr, Le {Le:.2f}, total flux {math.pi * Le * area:.2f} W")
