#!/usr/bin/python3
"""Region-exact re-solve: is a mesh optimal inside regions of itself, over candidate Steiner points?

A research check of the optimiser (`mwst triangulate --method opt`), not part of the library or of
the tests. It grows disjoint regions of about --region-vertices vertices from the mesh's triangles
(breadth first, from triangles taken in a seeded random order), keeps each region's boundary fixed,
and finds the lightest triangulation of the region whose vertices are

  - mandatory: the region's boundary vertices and the input vertices inside it;
  - optional:  the Steiner points inside it and candidate points: a jittered grid of about
               --grid-points points over the region (`grid`), or the centroid of every triangle and
               a jittered midpoint of every interior edge (`adaptive`), or both; and with
               --segment-points K, K points on each of the region's boundary edges that lie on the
               domain's boundary (a segment or hull edge, split where they are used).

The lightest triangulation is an integer program over the candidate triangles (the triangles of
candidate points inside the region with no mandatory point inside or on them, plus the region's
own triangles): minimise the sum of their half perimeters subject to, for every candidate edge,
"as many chosen triangles on its left as on its right" (interior edges) or "exactly one on the
inside" (each piece of the region's boundary edges). The number of chosen triangles covering a
point is then the same on both sides of every edge, and 1 next to the boundary, so it is 1
everywhere: the chosen triangles tile the region, each optional point is a vertex or unused, and
a mandatory point cannot lie inside a triangle, so it is a vertex (triangle variables and such
covering constraints are the integer programs of optimal triangulations; see De Loera, Rambau
and Santos, "Triangulations", 2010, on the universal polytope). A gain means a lighter
triangulation of that region exists with those points; no gain means the mesh is the lightest
there among them. Geometry here is floating point (it only searches: a gain would have to be
confirmed by building the mesh and running `mwst check`).

Needs python3-numpy and python3-scipy (Debian; scipy >= 1.9 for its HiGHS `milp`).

usage: scripts/region_exact.py INPUT.poly|.node MESH_PREFIX [--regions 4] [--region-vertices 40]
           [--candidates grid|adaptive|both] [--grid-points 60] [--segment-points 0] [--seed 1]
           [--time-limit 300]
MESH_PREFIX.node/.ele is the mesh (`mwst triangulate INPUT -o MESH_PREFIX`); its first vertices are
the input's, in order (as mwst writes them).
"""
import argparse
import math
import random
import sys

import numpy as np
from scipy.optimize import Bounds, LinearConstraint, milp
from scipy.sparse import coo_matrix


def read_table(path):
    """Lines of a Triangle file as token lists, comments and blank lines dropped."""
    rows = []
    with open(path) as f:
        for line in f:
            tokens = line.split('#', 1)[0].split()
            if tokens:
                rows.append(tokens)
    return rows


def read_points(path):
    """The vertex section of a .node or .poly file: (coordinates, first index)."""
    rows = read_table(path)
    n = int(rows[0][0])
    pts = np.array([[float(r[1]), float(r[2])] for r in rows[1:1 + n]])
    first = int(rows[1][0]) if n else 0
    return pts, first


def read_triangles(path, first):
    rows = read_table(path)
    n = int(rows[0][0])
    return np.array([[int(r[k]) - first for k in (1, 2, 3)] for r in rows[1:1 + n]])


def orient(a, b, c):
    """Twice the signed area of abc, over arrays of points (last axis x, y)."""
    return ((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
            - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))


def inside(points, loops):
    """Even-odd rule over the region's boundary loops, for an array of points."""
    result = np.zeros(len(points), dtype=bool)
    for loop in loops:
        for a, b in zip(loop, np.roll(loop, -1, axis=0)):
            straddles = (a[1] > points[:, 1]) != (b[1] > points[:, 1])
            with np.errstate(divide='ignore', invalid='ignore'):
                x = a[0] + (points[:, 1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
            result ^= straddles & (x > points[:, 0])
    return result


class Mesh:
    def __init__(self, pts, tris):
        self.pts, self.tris = pts, tris
        self.edge_triangles = {}
        for t, (a, b, c) in enumerate(tris):
            for u, v in ((a, b), (b, c), (c, a)):
                self.edge_triangles.setdefault((min(u, v), max(u, v)), []).append(t)
        self.weight = sum(math.dist(pts[u], pts[v]) for u, v in self.edge_triangles)

    def neighbours(self, t):
        a, b, c = self.tris[t]
        for u, v in ((a, b), (b, c), (c, a)):
            for s in self.edge_triangles[(min(u, v), max(u, v))]:
                if s != t:
                    yield s

    def grow_region(self, start, max_vertices, taken):
        """Triangles reached breadth first from start while the region has at most max_vertices."""
        region, members, verts = [start], {start}, set(self.tris[start])
        frontier = [start]
        while frontier:
            grown = []
            for t in frontier:
                for s in self.neighbours(t):
                    if s in members or s in taken:
                        continue
                    more = verts | set(self.tris[s])
                    if len(more) <= max_vertices:
                        members.add(s)
                        region.append(s)
                        verts = more
                        grown.append(s)
            frontier = grown
        return region, members, verts


def half_perimeter(a, b, c):
    return 0.5 * sum(np.linalg.norm(p - q, axis=-1) for p, q in ((a, b), (b, c), (c, a)))


def solve_region(mesh, region, members, verts, n_input, args, rng):
    pts, tris = mesh.pts, mesh.tris
    # The region's boundary edges, directed with the region on their left.
    boundary = []
    for t in region:
        a, b, c = tris[t]
        for u, v in ((a, b), (b, c), (c, a)):
            if not any(s in members for s in mesh.edge_triangles[(min(u, v), max(u, v))] if s != t):
                boundary.append((u, v))
    boundary_edges = set(boundary)
    boundary_vertices = {u for e in boundary for u in e}
    successor = {}
    for u, v in boundary:
        successor.setdefault(u, []).append(v)
    loops, seen = [], set()
    for e in boundary:
        loop = []
        while e not in seen:
            seen.add(e)
            loop.append(pts[e[0]])
            later = [w for w in successor[e[1]] if (e[1], w) not in seen]
            if not later:
                break
            e = (e[1], later[0])
        if loop:
            loops.append(np.array(loop))
    interior = verts - boundary_vertices
    mandatory = sorted(boundary_vertices | {v for v in interior if v < n_input})
    steiner = sorted(v for v in interior if v >= n_input)
    index = {v: i for i, v in enumerate(mandatory + steiner)}
    cand = [pts[v] for v in mandatory + steiner]
    area = sum(abs(orient(pts[a], pts[b], pts[c])) / 2 for a, b, c in (tris[t] for t in region))
    lo, hi = np.min(cand, axis=0), np.max(cand, axis=0)
    if args.candidates in ('grid', 'both'):
        h = math.sqrt(area / args.grid_points)
        grid = [(x + rng.uniform(-0.2, 0.2) * h, y + rng.uniform(-0.2, 0.2) * h)
                for x in np.arange(lo[0] + h / 2, hi[0], h)
                for y in np.arange(lo[1] + h / 2, hi[1], h)]
        grid = np.array(grid).reshape(-1, 2)
        cand += list(grid[inside(grid, loops)])
    if args.candidates in ('adaptive', 'both'):
        for t in region:
            a, b, c = tris[t]
            cand.append((pts[a] + pts[b] + pts[c]) / 3)
            for u, v in ((a, b), (b, c), (c, a)):
                if u < v and (u, v) not in boundary_edges and (v, u) not in boundary_edges:
                    d = pts[v] - pts[u]
                    cand.append((pts[u] + pts[v]) / 2 + d * rng.uniform(-0.05, 0.05)
                                + np.array([-d[1], d[0]]) * rng.uniform(-0.02, 0.02))
    # Each boundary edge of the region is a chain: its two ends and, where it lies on the domain's
    # boundary (a segment piece, no triangle beyond it), --segment-points optional points on it.
    # Any two points of a chain make a boundary edge ("along" the chain) that covers the pieces
    # between them; every piece is covered exactly once from inside.
    chains = []
    for u, v in boundary:
        chain = [index[u]]
        if len(mesh.edge_triangles[(min(u, v), max(u, v))]) == 1:
            for k in range(1, args.segment_points + 1):
                chain.append(len(cand))
                cand.append(pts[u] + (pts[v] - pts[u]) * (k / (args.segment_points + 1)))
        chain.append(index[v])
        chains.append(chain)
    along = {}  # directed edge (a, b) along a chain -> (chain number, first piece, end piece)
    for c, chain in enumerate(chains):
        for x in range(len(chain)):
            for y in range(x + 1, len(chain)):
                along[(chain[x], chain[y])] = (c, x, y)
    along_undirected = {(min(e), max(e)) for e in along}
    segment_points = {x for chain in chains for x in chain[1:-1]}
    on_chain = [set(chain) for chain in chains]
    P = np.array(cand)
    m, n_mandatory = len(P), len(mandatory)

    # Candidate edges: a boundary edge, or one that crosses no boundary edge and has its midpoint
    # inside the region.
    iu, ju = np.triu_indices(m, 1)
    ok = np.ones(len(iu), dtype=bool)
    for c, chain in enumerate(chains):
        s, t = chain[0], chain[-1]
        o1, o2 = orient(P[iu], P[ju], P[s]), orient(P[iu], P[ju], P[t])
        o3, o4 = orient(P[s], P[t], P[iu]), orient(P[s], P[t], P[ju])
        members = np.array(sorted(on_chain[c]))
        touches = np.isin(iu, members) | np.isin(ju, members)
        ok &= ~((o1 * o2 < 0) & (o3 * o4 < 0) & ~touches)
    ok &= inside((P[iu] + P[ju]) / 2, loops)
    ok |= np.array([(i, j) in along_undirected for i, j in zip(iu, ju)], dtype=bool)
    edge_ok = np.zeros((m, m), dtype=bool)
    edge_ok[iu, ju] = ok
    edge_ok[ju, iu] = ok
    reversed_boundary = np.zeros((m, m), dtype=bool)
    for s, t in along:
        reversed_boundary[t, s] = True

    triangles = [tuple(index[v] for v in tris[t]) for t in region]  # the region's own, always
    own_triangles = {tuple(sorted(t)) for t in triangles}
    for i in range(m):
        js, ks = np.triu_indices(m - i - 1, 1)
        js, ks = js + i + 1, ks + i + 1
        keep = edge_ok[i, js] & edge_ok[js, ks] & edge_ok[ks, i]
        js, ks = js[keep], ks[keep]
        o = orient(np.broadcast_to(P[i], (len(js), 2)), P[js], P[ks])
        js, ks, o = js[o != 0], ks[o != 0], o[o != 0]
        jj, kk = np.where(o > 0, js, ks), np.where(o > 0, ks, js)  # counterclockwise i, jj, kk
        ii = np.full(len(jj), i)
        keep = ~(reversed_boundary[ii, jj] | reversed_boundary[jj, kk] | reversed_boundary[kk, ii])
        ii, jj, kk = ii[keep], jj[keep], kk[keep]
        a, b, c = P[ii], P[jj], P[kk]
        keep = inside((a + b + c) / 3, loops)
        for q in range(n_mandatory):
            covers = ((orient(a, b, P[q]) >= 0) & (orient(b, c, P[q]) >= 0)
                      & (orient(c, a, P[q]) >= 0))
            keep &= ~(covers & (ii != q) & (jj != q) & (kk != q))
        for t in zip(ii[keep].tolist(), jj[keep].tolist(), kk[keep].tolist()):
            if tuple(sorted(t)) not in own_triangles:
                triangles.append(t)
    T = np.array(triangles)
    cost = half_perimeter(P[T[:, 0]], P[T[:, 1]], P[T[:, 2]])

    # Edge-flow rows: +1 for a triangle on an edge's left, -1 on its right (= 0); a boundary piece
    # is covered by exactly one triangle (= 1).
    rows, cols, vals, lower = [], [], [], []
    row_of = {}

    def add(key, t, value, bound):
        if key not in row_of:
            row_of[key] = len(lower)
            lower.append(bound)
        rows.append(row_of[key])
        cols.append(t)
        vals.append(value)

    for t, (i, j, k) in enumerate(T.tolist()):
        for u, v in ((i, j), (j, k), (k, i)):
            if (u, v) in along:
                c, first, end = along[(u, v)]
                for piece in range(first, end):
                    add(('piece', c, piece), t, 1, 1)
            else:
                add((min(u, v), max(u, v)), t, 1 if u < v else -1, 0)
    A = coo_matrix((vals, (rows, cols)), shape=(len(lower), len(T))).tocsr()
    result = milp(cost, constraints=LinearConstraint(A, lower, lower), integrality=np.ones(len(T)),
                  bounds=Bounds(0, 1), options={'time_limit': args.time_limit})
    current = float(cost[:len(region)].sum())
    if result.x is None:
        return dict(triangles=len(region), vertices=len(verts), steiner=len(steiner), candidates=m,
                    candidate_triangles=len(T), current=current, best=None, used=None,
                    status=result.message)
    chosen = T[result.x > 0.5]
    used_points = {v for t in chosen.tolist() for v in t if v >= n_mandatory}
    used = len(used_points)
    if segment_points:
        used = f"{used} ({len(used_points & segment_points)} on segments)"
    return dict(triangles=len(region), vertices=len(verts), steiner=len(steiner), candidates=m,
                candidate_triangles=len(T), current=current, best=float(result.fun), used=used,
                status='optimal' if result.status == 0 else result.message)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('input')
    parser.add_argument('mesh_prefix')
    parser.add_argument('--regions', type=int, default=4)
    parser.add_argument('--region-vertices', type=int, default=40)
    parser.add_argument('--candidates', choices=['grid', 'adaptive', 'both'], default='grid')
    parser.add_argument('--grid-points', type=int, default=60)
    parser.add_argument('--segment-points', type=int, default=0,
                        help='optional points on each boundary edge that lies on the domain boundary')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--time-limit', type=float, default=300)
    args = parser.parse_args()

    input_points, _ = read_points(args.input)
    pts, first = read_points(args.mesh_prefix + '.node')
    tris = read_triangles(args.mesh_prefix + '.ele', first)
    n_input = len(input_points)
    if len(pts) < n_input or not np.array_equal(pts[:n_input], input_points):
        sys.exit(f'{args.mesh_prefix}.node: its first {n_input} vertices are not the input\'s')
    mesh = Mesh(pts, tris)
    rng = random.Random(args.seed)
    order = list(range(len(tris)))
    rng.shuffle(order)
    taken = set()
    print(f'{args.mesh_prefix}: {len(pts)} vertices ({len(pts) - n_input} Steiner), '
          f'{len(tris)} triangles, weight {mesh.weight:.6f}; regions of <= '
          f'{args.region_vertices} vertices, {args.candidates} candidates')
    print('| region | triangles | vertices | Steiner | candidates | candidate triangles '
          '| weight now | lightest | gain | Steiner used | status |')
    print('|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|')
    done = 0
    for start in order:
        if done == args.regions:
            break
        if start in taken:
            continue
        region, members, verts = mesh.grow_region(start, args.region_vertices, taken)
        if len(region) < 6:
            continue
        taken |= members
        done += 1
        r = solve_region(mesh, region, members, verts, n_input, args, rng)
        best = f"{r['best']:.6f}" if r['best'] is not None else '-'
        gain = f"{r['current'] - r['best']:.6f}" if r['best'] is not None else '-'
        print(f"| {done} | {r['triangles']} | {r['vertices']} | {r['steiner']} | {r['candidates']} | "
              f"{r['candidate_triangles']} | {r['current']:.6f} | {best} | {gain} | {r['used']} | {r['status']} |",
              flush=True)


if __name__ == '__main__':
    main()
