#!/usr/bin/env python3
"""Writes the example meshes of examples/meshes/ (mesh obstacles, docs/design.md §14):

  mannequin.obj  a torso (hips, waist, chest, shoulders, a neck stub; no arms), the zero level set
                 of a smooth union of ellipsoids and capsules, by marching tetrahedra, its uneven
                 triangles then relaxed along the surface. It stands on its axis x = 0, y = 0, from
                 z = -1.3 (the bottom of the hips) to z = -0.6 (the top of the neck), 0.45 m across
                 the shoulders (along x) and about 0.24 m deep (along y), so that a horizontal 1 m
                 cloth at z = 0 centred on the z axis (a scene's `placement = horizontal`) falls
                 onto its shoulders.
  sphere.obj     the sphere of examples/scenes/drape.scene (centre 0,0,-0.3, radius 0.25) as an
                 icosphere: each face of an icosahedron cut into n^2 triangles, every vertex pushed
                 out radially onto the sphere, n the smallest frequency whose sagitta (the largest
                 distance between the sphere and a facet) is at most 1 mm.
  table.obj      the rounded box of examples/scenes/table.scene (centre 0.35,0,-0.2, size 1,1.4,0.2,
                 rounding 0.02): flat faces as grids, rounded edges as quarter-cylinders and
                 corners as sphere octants, every vertex on the surface, the quarter circles cut
                 into the fewest equal arcs whose sagitta is at most 0.5 mm.
  paddle/paddle0000.obj ... paddle0020.obj
                 an animated mesh (a sequence at 10 frames per second, t = 0 to 2 s): an ellipsoid
                 of radii 0.2, 0.08, 0.08 (m) spinning a half turn per second about the y axis while
                 its centre follows examples/scenes/pushed-sphere-path.csv (at 0.5,-0.4,-0.6 until
                 0.5 s, then 0.8 m along y in 1.5 s), through the cloth hanging in the x-z plane
                 (examples/scenes/paddle.scene). A rotation no rigid motion= can give: every frame
                 is the same icosphere of frequency 4, so the frames share one topology.

Each mesh is checked before it is written: closed (every edge in exactly two triangles), oriented
consistently (every directed edge once, normals outward), no triangle with a repeated vertex or
zero area, no two triangles that share no vertex crossing each other, a positive signed volume
(for the sphere and the box within the tessellation's expected shortfall of the analytic volume).
The sagittas and counts are printed and written in each file's header.

Deterministic: the same files on every run (the mannequin and the sphere use only arithmetic and
square roots, exact in IEEE arithmetic on every machine; the table's few tangents come from the C
library, the paddle's sines and cosines too, and every coordinate is written to 9 significant digits).
Python 3 standard library only.

    scripts/make-example-meshes.py [--out DIR]    (default: examples/meshes beside this script)
"""

import argparse
import math
import pathlib

SCRIPT = "scripts/make-example-meshes.py"

# ---- vectors ---------------------------------------------------------------------------------


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scaled(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def normalized(a):
    return scaled(a, 1.0 / norm(a))


def lerp(a, b, t):
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2]))


# ---- checks ----------------------------------------------------------------------------------


def signed_volume(vertices, triangles):
    """Sum of the tetrahedra (origin, triangle): the enclosed volume of a closed outward mesh."""
    return sum(dot(vertices[a], cross(vertices[b], vertices[c])) for a, b, c in triangles) / 6.0


def triangle_area(vertices, t):
    a, b, c = (vertices[i] for i in t)
    return 0.5 * norm(cross(sub(b, a), sub(c, a)))


def orient(a, b, c, d):
    """Six times the signed volume of the tetrahedron abcd."""
    return dot(sub(b, a), cross(sub(c, a), sub(d, a)))


def segment_crosses_triangle(p, q, a, b, c):
    """Whether the segment pq passes through the triangle abc (a proper crossing, in floating point:
    the segment's ends on strict opposite sides of the plane and the crossing point strictly inside)."""
    sp, sq = orient(a, b, c, p), orient(a, b, c, q)
    if sp * sq >= 0.0:
        return False
    s1, s2, s3 = orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)
    return (s1 > 0 and s2 > 0 and s3 > 0) or (s1 < 0 and s2 < 0 and s3 < 0)


def crossing_pairs(vertices, triangles):
    """The pairs of triangles sharing no vertex where an edge of one crosses the other, through a
    uniform grid of the triangles' boxes (cell side: the longest edge)."""
    boxes = []
    for t in triangles:
        points = [vertices[i] for i in t]
        boxes.append((tuple(min(p[k] for p in points) for k in range(3)),
                      tuple(max(p[k] for p in points) for k in range(3))))
    side = max(max(hi[k] - lo[k] for k in range(3)) for lo, hi in boxes)
    cells = {}
    for index, (lo, hi) in enumerate(boxes):
        first = [math.floor(lo[k] / side) for k in range(3)]
        last = [math.floor(hi[k] / side) for k in range(3)]
        for i in range(first[0], last[0] + 1):
            for j in range(first[1], last[1] + 1):
                for k in range(first[2], last[2] + 1):
                    cells.setdefault((i, j, k), []).append(index)
    seen, crossings = set(), 0
    for members in cells.values():
        for x in range(len(members)):
            for y in range(x + 1, len(members)):
                s, t = members[x], members[y]
                if (s, t) in seen or set(triangles[s]) & set(triangles[t]):
                    continue
                seen.add((s, t))
                (ls, hs), (lt, ht) = boxes[s], boxes[t]
                if any(hs[k] < lt[k] or ht[k] < ls[k] for k in range(3)):
                    continue
                if triangles_cross(vertices, triangles[s], triangles[t]):
                    crossings += 1
    return crossings


def triangles_cross(vertices, s, t):
    for first, second in ((s, t), (t, s)):
        a, b, c = (vertices[i] for i in second)
        for e in range(3):
            if segment_crosses_triangle(vertices[first[e]], vertices[first[(e + 1) % 3]], a, b, c):
                return True
    return False


def check_mesh(name, vertices, triangles, expected_volume=None, volume_tolerance=0.0):
    """Raises SystemExit unless the mesh is closed, consistently oriented outward, free of degenerate
    triangles and crossings, and (given expected_volume) encloses that volume within the tolerance.
    Returns the signed volume."""
    directed = {}
    for t in triangles:
        if len(set(t)) != 3:
            raise SystemExit(f"{name}: triangle {t} repeats a vertex")
        if triangle_area(vertices, t) <= 0.0:
            raise SystemExit(f"{name}: triangle {t} has no area")
        for e in range(3):
            edge = (t[e], t[(e + 1) % 3])
            if edge in directed:
                raise SystemExit(f"{name}: edge {edge} twice in the same direction (not oriented, or not manifold)")
            directed[edge] = True
    for a, b in directed:
        if (b, a) not in directed:
            raise SystemExit(f"{name}: edge ({a}, {b}) in one triangle only (not closed)")
    volume = signed_volume(vertices, triangles)
    if volume <= 0.0:
        raise SystemExit(f"{name}: signed volume {volume} is not positive (normals inward)")
    if expected_volume is not None and abs(volume - expected_volume) > volume_tolerance * expected_volume:
        raise SystemExit(f"{name}: volume {volume} is not within {volume_tolerance} of {expected_volume}")
    crossings = crossing_pairs(vertices, triangles)
    if crossings:
        raise SystemExit(f"{name}: {crossings} pairs of triangles cross each other")
    return volume


def barycentric_samples(subdivisions):
    n = subdivisions
    return [(i / n, j / n, (n - i - j) / n) for i in range(n + 1) for j in range(n + 1 - i)]


def sagitta(vertices, triangles, depth, subdivisions=32):
    """The largest depth(p) of a facet point p below the true surface, sampled on each facet's
    barycentric grid (facets whose centroid lies on the surface are flat pieces of it)."""
    samples = barycentric_samples(subdivisions)
    largest = 0.0
    for t in triangles:
        a, b, c = (vertices[i] for i in t)
        if depth(scaled(add(a, add(b, c)), 1.0 / 3.0)) < 1e-12:
            continue  # a facet of a flat face: on the surface everywhere
        for u, v, w in samples:
            p = (u * a[0] + v * b[0] + w * c[0], u * a[1] + v * b[1] + w * c[1], u * a[2] + v * b[2] + w * c[2])
            largest = max(largest, depth(p))
    return largest


def write_obj(path, header, vertices, triangles):
    lines = [f"# Generated by {SCRIPT}; do not edit, rerun the script."]
    lines += [f"# {line}" if line else "#" for line in header]
    lines += [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
    path.write_text("\n".join(lines) + "\n", encoding="ascii")


def extents(vertices):
    return ([min(v[k] for v in vertices) for k in range(3)], [max(v[k] for v in vertices) for k in range(3)])


# ---- sphere ----------------------------------------------------------------------------------

SPHERE_CENTER = (0.0, 0.0, -0.3)
SPHERE_RADIUS = 0.25
SPHERE_SAGITTA = 1e-3


def icosahedron():
    """The unit icosahedron's 12 vertices and 20 outward faces."""
    g = (1.0 + math.sqrt(5.0)) / 2.0
    points = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g),
              (0, -1, -g), (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
             (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return [normalized(p) for p in points], faces


def icosphere(frequency, center, radius):
    """Each icosahedron face (a, b, c) cut into frequency^2 triangles by the points
    (i a + j b + k c) / n, i + j + k = n, pushed radially onto the sphere. A point is named by its
    corners' weights, so the faces sharing an edge share its points."""
    corners, faces = icosahedron()
    n = frequency
    index, vertices, triangles = {}, [], []

    def point(face, i, j, k):
        key = tuple(sorted((face[m], w) for m, w in enumerate((i, j, k)) if w))
        if key not in index:
            flat = (0.0, 0.0, 0.0)
            for corner, weight in key:
                flat = add(flat, scaled(corners[corner], weight / n))
            index[key] = len(vertices)
            vertices.append(add(center, scaled(normalized(flat), radius)))
        return index[key]

    for face in faces:
        for i in range(n):
            for j in range(n - i):
                k = n - i - j
                # (i, j, k) -> (i+1, j, k-1) -> (i, j+1, k-1) keeps the face's (a, b, c) order.
                triangles.append((point(face, i, j, k), point(face, i + 1, j, k - 1), point(face, i, j + 1, k - 1)))
                if i + j + 1 < n:
                    triangles.append((point(face, i + 1, j, k - 1), point(face, i + 1, j + 1, k - 2),
                                      point(face, i, j + 1, k - 1)))
    return vertices, triangles


def closest_point_on_triangle(p, a, b, c):
    """Ericson, Real-Time Collision Detection, 5.1.5."""
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0 and d2 <= 0:
        return a
    bp = sub(p, b)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return b
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        return add(a, scaled(ab, d1 / (d1 - d3)))
    cp = sub(p, c)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return c
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        return add(a, scaled(ac, d2 / (d2 - d6)))
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        return add(b, scaled(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))))
    denominator = 1.0 / (va + vb + vc)
    return add(a, add(scaled(ab, vb * denominator), scaled(ac, vc * denominator)))


def sphere_sagitta(vertices, triangles, center, radius):
    """Exactly: the radius less the distance from the centre to the facet nearest it."""
    return max(radius - norm(sub(closest_point_on_triangle(center, *(vertices[i] for i in t)), center))
               for t in triangles)


def make_sphere(out):
    frequency = 1
    while True:
        vertices, triangles = icosphere(frequency, SPHERE_CENTER, SPHERE_RADIUS)
        depth = sphere_sagitta(vertices, triangles, SPHERE_CENTER, SPHERE_RADIUS)
        if depth <= SPHERE_SAGITTA:
            break
        frequency += 1
    exact = 4.0 / 3.0 * math.pi * SPHERE_RADIUS ** 3
    # An inscribed polytope falls short of the ball by less than its sagitta times the sphere's area.
    volume = check_mesh("sphere", vertices, triangles, exact, 3.0 * depth / SPHERE_RADIUS)
    header = [
        "The sphere of examples/scenes/drape.scene: centre 0,0,-0.3, radius 0.25 (m), every vertex on it.",
        f"Icosphere of frequency {frequency}: each icosahedron face cut into {frequency}^2 triangles, pushed out",
        "radially; the smallest frequency whose sagitta (the largest distance between sphere and facet) is",
        f"at most 1 mm. Sagitta {depth * 1e3:.3f} mm; {len(vertices)} vertices, {len(triangles)} triangles;",
        f"volume {volume:.6f} m^3 against the ball's {exact:.6f}.",
    ]
    write_obj(out / "sphere.obj", header, vertices, triangles)
    return f"sphere.obj: frequency {frequency}, {len(triangles)} triangles, sagitta {depth * 1e3:.3f} mm, " \
           f"volume {volume:.6f} of {exact:.6f} m^3"


# ---- table -----------------------------------------------------------------------------------

TABLE_CENTER = (0.35, 0.0, -0.2)
TABLE_SIZE = (1.0, 1.4, 0.2)
TABLE_ROUNDING = 0.02
TABLE_SAGITTA = 0.5e-3
TABLE_FLAT_SPACING = 0.05  # the flat faces' grid, at most this (m)


def rounded_box_axis_samples(half, rounding, flat_cells, arcs_per_eighth):
    """One axis's coordinates of the grid on the box of half size half + rounding that the surface
    is made from: the flat part [-half, half] in flat_cells equal cells, then half + rounding tan(θ)
    for θ in equal steps up to 45° on either side, so that the rounding's arcs are equal."""
    flat = [-half + 2.0 * half * i / flat_cells for i in range(flat_cells + 1)]
    outer = [half + rounding * math.tan(math.pi / 4.0 * m / arcs_per_eighth) for m in range(1, arcs_per_eighth + 1)]
    return [-x for x in reversed(outer)] + flat + outer


def rounded_box(center, size, rounding, arcs_per_eighth):
    """The surface of the rounded box (the inner box of half sizes size/2 - rounding, grown by the
    rounding) from the grid on the faces of the box of half sizes size/2: a grid point g maps to
    q + rounding (g - q)/|g - q|, q its nearest point of the inner box. On a flat face g - q is the
    face normal times the rounding; over an edge's strip it turns by the equal steps of θ; over a
    corner it is a cube-sphere patch of the octant. Faces of the grid box are quads, split along
    the shorter diagonal of the mapped points, wound counter-clockwise from outside."""
    half = [s / 2.0 - rounding for s in size]
    samples = [rounded_box_axis_samples(half[k], rounding, max(1, math.ceil(2.0 * half[k] / TABLE_FLAT_SPACING)),
                                        arcs_per_eighth) for k in range(3)]
    index, vertices, triangles = {}, [], []

    def point(key):
        if key not in index:
            g = [samples[k][key[k]] for k in range(3)]
            q = [min(max(g[k], -half[k]), half[k]) for k in range(3)]
            n = normalized(sub(g, q))
            index[key] = len(vertices)
            vertices.append(add(center, add(q, scaled(n, rounding))))
        return index[key]

    for axis in range(3):
        b, c = (axis + 1) % 3, (axis + 2) % 3  # b x c = axis
        for side in (0, len(samples[axis]) - 1):
            for i in range(len(samples[b]) - 1):
                for j in range(len(samples[c]) - 1):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        key = [0, 0, 0]
                        key[axis], key[b], key[c] = side, i + di, j + dj
                        quad.append(point(tuple(key)))
                    if side == 0:
                        quad.reverse()  # the face at -axis faces -axis
                    triangles += split_quad(vertices, quad)
    return vertices, triangles


def split_quad(vertices, quad):
    p = [vertices[i] for i in quad]
    if norm(sub(p[2], p[0])) <= norm(sub(p[3], p[1])):
        return [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
    return [(quad[0], quad[1], quad[3]), (quad[1], quad[2], quad[3])]


def rounded_box_depth(center, size, rounding):
    """depth(p) = rounding - (distance from p to the inner box): how far below the surface a point
    between the inner box and the surface lies."""
    half = [s / 2.0 - rounding for s in size]

    def depth(p):
        local = sub(p, center)
        outside = [max(abs(local[k]) - half[k], 0.0) for k in range(3)]
        return rounding - norm(outside)
    return depth


def rounded_box_volume(size, rounding):
    a, b, c = (s - 2.0 * rounding for s in size)
    r = rounding
    return a * b * c + 2.0 * r * (a * b + b * c + c * a) + math.pi * r * r * (a + b + c) + 4.0 / 3.0 * math.pi * r ** 3


def make_table(out):
    arcs = 1
    while True:
        vertices, triangles = rounded_box(TABLE_CENTER, TABLE_SIZE, TABLE_ROUNDING, arcs)
        depth = sagitta(vertices, triangles, rounded_box_depth(TABLE_CENTER, TABLE_SIZE, TABLE_ROUNDING))
        if depth <= TABLE_SAGITTA:
            break
        arcs += 1
    exact = rounded_box_volume(TABLE_SIZE, TABLE_ROUNDING)
    area = 2.0 * (TABLE_SIZE[0] * TABLE_SIZE[1] + TABLE_SIZE[1] * TABLE_SIZE[2] + TABLE_SIZE[2] * TABLE_SIZE[0])
    # Only the rounding falls short of the surface, by at most the sagitta over less than the area.
    volume = check_mesh("table", vertices, triangles, exact, 1.5 * depth * area / exact)
    header = [
        "The rounded box of examples/scenes/table.scene: centre 0.35,0,-0.2, size 1,1.4,0.2, rounding 0.02 (m),",
        "every vertex on its surface: flat faces as grids of cells up to 5 cm, rounded edges as quarter-cylinders",
        f"and corners as sphere octants, each quarter circle in {2 * arcs} equal arcs, the fewest whose sagitta (the",
        "largest distance between the rounding and a facet, sampled on each facet) is at most 0.5 mm.",
        f"Sagitta {depth * 1e3:.3f} mm; {len(vertices)} vertices, {len(triangles)} triangles;",
        f"volume {volume:.6f} m^3 against the rounded box's {exact:.6f}.",
    ]
    write_obj(out / "table.obj", header, vertices, triangles)
    return f"table.obj: {2 * arcs} arcs per quarter circle, {len(triangles)} triangles, sagitta {depth * 1e3:.3f} mm, " \
           f"volume {volume:.6f} of {exact:.6f} m^3"


# ---- mannequin -------------------------------------------------------------------------------

# The grid the torso is sampled on: spacing (m) and a box with the body well inside it.
MANNEQUIN_SPACING = 0.032
MANNEQUIN_BOX = ((-0.30, -0.20, -1.36), (0.30, 0.20, -0.54))
# Where a surface point may sit along its grid edge, away from both ends, so that no triangle
# shrinks to a sliver at a grid point.
MANNEQUIN_EDGE_MARGIN = 0.05
MANNEQUIN_RELAXATION_ROUNDS = 5


def ellipsoid(p, center, radii):
    """Quilez's bound for an ellipsoid's signed distance: exact on its surface, smooth elsewhere."""
    q = [(p[k] - center[k]) / radii[k] for k in range(3)]
    k0 = math.sqrt(dot(q, q))
    k1 = math.sqrt(sum((q[k] / radii[k]) ** 2 for k in range(3)))
    return k0 * (k0 - 1.0) / k1 if k1 > 0.0 else -min(radii)


def capsule(p, a, b, radius):
    ab, ap = sub(b, a), sub(p, a)
    t = min(max(dot(ap, ab) / dot(ab, ab), 0.0), 1.0)
    return norm(sub(ap, scaled(ab, t))) - radius


def smooth_union(d1, d2, k):
    """Quilez's polynomial smooth minimum: min(d1, d2) rounded over a blend of width k."""
    h = max(k - abs(d1 - d2), 0.0) / k
    return min(d1, d2) - h * h * k / 4.0


def torso(p):
    """The torso's signed distance (negative inside; m). Its parts, bottom to top."""
    hips = ellipsoid(p, (0.0, 0.0, -1.165), (0.165, 0.115, 0.135))
    waist = ellipsoid(p, (0.0, 0.0, -1.0), (0.13, 0.095, 0.13))
    chest = ellipsoid(p, (0.0, 0.005, -0.84), (0.16, 0.115, 0.15))
    shoulders = capsule(p, (-0.165, 0.0, -0.715), (0.165, 0.0, -0.715), 0.06)
    neck = capsule(p, (0.0, 0.0, -0.74), (0.0, 0.0, -0.655), 0.055)
    body = smooth_union(smooth_union(hips, waist, 0.08), chest, 0.08)
    body = smooth_union(body, shoulders, 0.07)
    return smooth_union(body, neck, 0.04)


# The cube's corners by bits (x = bit 0, y = bit 1, z = bit 2), and Kuhn's six tetrahedra around
# its diagonal 0-7, one per order of the axes: the same split in every cube, so neighbouring cubes'
# tetrahedra meet face to face.
KUHN_TETRAHEDRA = [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)]


def edge_root(f, a, b, fa, fb):
    """The point of the grid edge ab (fa < 0 < fb or the reverse) where f vanishes, by bisection
    on f itself, kept MANNEQUIN_EDGE_MARGIN of the edge away from either end."""
    lo, hi = 0.0, 1.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if (f(lerp(a, b, mid)) < 0.0) == (fa < 0.0):
            lo = mid
        else:
            hi = mid
    t = min(max(0.5 * (lo + hi), MANNEQUIN_EDGE_MARGIN), 1.0 - MANNEQUIN_EDGE_MARGIN)
    return lerp(a, b, t)


def marching_tetrahedra(f, box, spacing):
    """The zero level set of f as a closed, outward-wound triangle mesh. Per tetrahedron of the
    grid, the surface separating its inside corners (f < 0) from its outside ones is one triangle
    or a quad of two; every surface point is on a grid edge and named by it, so neighbours share
    it. Such a surface never crosses itself: each piece stays in its tetrahedron and meets its
    neighbours' on their common faces. The winding is decided on the pieces through the edges'
    midpoints, which are planar and separate the corners, and kept when the points move along
    their edges to the roots."""
    lower, upper = box
    counts = [math.ceil((upper[k] - lower[k]) / spacing) for k in range(3)]
    grid = {}
    for i in range(counts[0] + 1):
        for j in range(counts[1] + 1):
            for k in range(counts[2] + 1):
                p = (lower[0] + i * spacing, lower[1] + j * spacing, lower[2] + k * spacing)
                value = f(p)
                grid[i, j, k] = (p, value if value != 0.0 else 1e-12)  # no corner exactly on the surface
    index, vertices, triangles = {}, [], []

    def surface_point(a, b):
        key = (min(a, b), max(a, b))
        if key not in index:
            (pa, fa), (pb, fb) = grid[key[0]], grid[key[1]]
            index[key] = len(vertices)
            vertices.append(edge_root(f, pa, pb, fa, fb))
        return index[key]

    for i in range(counts[0]):
        for j in range(counts[1]):
            for k in range(counts[2]):
                corners = [(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1)) for c in range(8)]
                signs = [grid[c][1] < 0.0 for c in corners]
                if all(signs) or not any(signs):
                    continue
                for tetrahedron in KUHN_TETRAHEDRA:
                    triangles += tetrahedron_surface([corners[c] for c in tetrahedron], grid, surface_point)
    return vertices, triangles


def tetrahedron_surface(corners, grid, surface_point):
    inside = [c for c in corners if grid[c][1] < 0.0]
    outside = [c for c in corners if grid[c][1] >= 0.0]
    if not inside or not outside:
        return []
    if len(inside) == 2:
        (a, b), (c, d) = inside, outside
        cycle = [(a, c), (a, d), (b, d), (b, c)]  # consecutive pairs share a corner: a quad
    else:
        single, others = (inside[0], outside) if len(inside) == 1 else (outside[0], inside)
        cycle = [(single, o) for o in others]
    midpoints = [lerp(grid[x][0], grid[y][0], 0.5) for x, y in cycle]
    normal = cross(sub(midpoints[1], midpoints[0]), sub(midpoints[2], midpoints[0]))
    centre_in = scaled([sum(grid[c][0][k] for c in inside) for k in range(3)], 1.0 / len(inside))
    centre_out = scaled([sum(grid[c][0][k] for c in outside) for k in range(3)], 1.0 / len(outside))
    if dot(normal, sub(centre_out, centre_in)) < 0.0:
        cycle.reverse()
    points = [surface_point(x, y) for x, y in cycle]
    if len(points) == 3:
        return [tuple(points)]
    return [(points[0], points[1], points[2]), (points[0], points[2], points[3])]


def gradient(f, p, step=1e-6):
    return tuple((f(add(p, e)) - f(sub(p, e))) / (2.0 * step) for e in ((step, 0, 0), (0, step, 0), (0, 0, step)))


def onto_level_set(f, p):
    """p moved along the gradient onto f = 0 (two Newton steps)."""
    for _ in range(2):
        g = gradient(f, p)
        p = sub(p, scaled(g, f(p) / dot(g, g)))
    return p


def relaxed(f, vertices, triangles, rounds):
    """Marching tetrahedra's triangles are uneven (slivers where the surface passes near a grid
    point): each round moves every vertex half way toward its neighbours' mean within the
    surface's tangent plane, then back onto the level set."""
    neighbours = [set() for _ in vertices]
    for t in triangles:
        for e in range(3):
            neighbours[t[e]].add(t[(e + 1) % 3])
            neighbours[t[(e + 1) % 3]].add(t[e])
    for _ in range(rounds):
        moved = []
        for p, around in zip(vertices, neighbours):
            mean = scaled([sum(vertices[j][k] for j in sorted(around)) for k in range(3)], 1.0 / len(around))
            normal = normalized(gradient(f, p))
            step = sub(mean, p)
            step = sub(step, scaled(normal, dot(step, normal)))
            moved.append(onto_level_set(f, add(p, scaled(step, 0.5))))
        vertices = moved
    return vertices


def check_winding_follows_gradient(f, vertices, triangles):
    """No triangle folded over by the relaxation: each faces the way f grows."""
    for t in triangles:
        a, b, c = (vertices[i] for i in t)
        if dot(cross(sub(b, a), sub(c, a)), gradient(f, scaled(add(a, add(b, c)), 1.0 / 3.0))) <= 0.0:
            raise SystemExit(f"mannequin: triangle {t} faces inward after relaxation")


def make_mannequin(out):
    vertices, triangles = marching_tetrahedra(torso, MANNEQUIN_BOX, MANNEQUIN_SPACING)
    vertices = relaxed(torso, vertices, triangles, MANNEQUIN_RELAXATION_ROUNDS)
    check_winding_follows_gradient(torso, vertices, triangles)
    volume = check_mesh("mannequin", vertices, triangles)
    lo, hi = extents(vertices)
    size = "x {:.3f} to {:.3f}, y {:.3f} to {:.3f}, z {:.3f} to {:.3f}".format(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])
    header = [
        "A torso (hips, waist, chest, shoulders, a neck stub; no arms) standing on the z axis (x = 0, y = 0),",
        "from z = -1.3 to z = -0.6, 0.45 m across the shoulders (along x): a horizontal 1 m cloth at z = 0",
        "centred on the z axis (placement = horizontal) falls onto its shoulders. The zero level set of a",
        f"smooth union of ellipsoids and capsules, by marching tetrahedra on a {MANNEQUIN_SPACING * 1e3:g} mm grid, then",
        f"{MANNEQUIN_RELAXATION_ROUNDS} rounds of tangential relaxation back onto the level set.",
        f"Extent (m): {size}; {len(vertices)} vertices, {len(triangles)} triangles; volume {volume:.6f} m^3.",
    ]
    write_obj(out / "mannequin.obj", header, vertices, triangles)
    return f"mannequin.obj: {len(triangles)} triangles, {size}, volume {volume:.6f} m^3"


# ---- paddle (an animated mesh) ------------------------------------------------------------------

PADDLE_RADII = (0.2, 0.08, 0.08)
PADDLE_FPS = 10
PADDLE_FRAMES = 21  # t = 0 to 2 s


def paddle_centre(t):
    """examples/scenes/pushed-sphere-path.csv: still until 0.5 s, then 0.8 m along y in 1.5 s."""
    w = min(max((t - 0.5) / 1.5, 0.0), 1.0)
    return (0.5, -0.4 + 0.8 * w, -0.6)


def make_paddle(out):
    unit, triangles = icosphere(4, (0.0, 0.0, 0.0), 1.0)
    folder = out / "paddle"
    folder.mkdir(parents=True, exist_ok=True)
    for frame in range(PADDLE_FRAMES):
        t = frame / PADDLE_FPS
        angle = math.pi * t  # a half turn per second about y
        c, s = math.cos(angle), math.sin(angle)
        centre = paddle_centre(t)
        vertices = []
        for p in unit:
            x, y, z = (p[k] * PADDLE_RADII[k] for k in range(3))
            vertices.append(add(centre, (c * x + s * z, y, -s * x + c * z)))
        check_mesh(f"paddle frame {frame}", vertices, triangles)
        header = [
            f"Frame {frame} of 0..{PADDLE_FRAMES - 1} (t = {t:g} s at {PADDLE_FPS} frames per second) of the paddle of",
            "examples/scenes/paddle.scene: an ellipsoid of radii 0.2, 0.08, 0.08 (m) spinning a half turn per second",
            "about the y axis, its centre on examples/scenes/pushed-sphere-path.csv. Icosphere of frequency 4;",
            f"{len(vertices)} vertices, {len(triangles)} triangles, the same in every frame.",
        ]
        write_obj(folder / f"paddle{frame:04d}.obj", header, vertices, triangles)
    return f"paddle/: {PADDLE_FRAMES} frames at {PADDLE_FPS} fps, {len(triangles)} triangles each"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=pathlib.Path,
                        default=pathlib.Path(__file__).resolve().parent.parent / "examples" / "meshes")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for make in (make_mannequin, make_sphere, make_table, make_paddle):
        print(make(args.out))


if __name__ == "__main__":
    main()
