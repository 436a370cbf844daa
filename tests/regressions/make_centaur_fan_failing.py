#!/usr/bin/env python3
"""Writes centaur_fan_before_fix.off: the valence-4 TOSCA centaur vertex of issue 21 in a closed genus-0 mesh
on which the OLD intrinsic Delaunay (before the flip-pairing fix) loses a vertex and the heat method returns inf.

    python3 make_centaur_fan_failing.py centaur_fan_before_fix.off

Deterministic: no arguments besides the output path, Python standard library only; writes the same bytes each
run (1432 vertices, 2860 faces, closed, connected, genus 0, mean edge 4.03, shortest edge 1.26 = a fan spoke).

The fan (vertex 0 = v, vertices 1..4 = w0..w3, faces (v, w_i, w_i+1)). Angles (at v, at w_i, at w_i+1):
    (131, 13, 36), (51, 112.86, 16.14), (43, 16, 121), (103, 57, 20) degrees
spokes v-w0..w3 = 3.292, 1.260, 4.176, 1.343 and rim edges 4.227, 3.522, 3.323, 3.825. The angles at v and all
other angles are those of the issue (13/36, 16/121, 57/20) except 114/16 → 112.86/16.14: the issue's rounded
angles are not exactly consistent, and fixing the three others and the angles at v determines that face.
This is the only cyclic order that closes with edges in 1.26-4.3. (An earlier attempt, make_cone_fan.py, had
the third face the wrong way round, (43, 121, 16): its fan did not close, so it was not this vertex, and it
did not fail before the fix; it was removed.)
With the correct order the spoke v-w2 faces 112.86 + 121 > 180 degrees: every intrinsic Delaunay flip
sequence starts by flipping it, leaving v of degree 3.

The fan is embedded with its one degree of freedom (angle between spokes w1 and w3) at BETA degrees. Vertex 5
(x) sits 1.385 from w0, and w0's outside is the two faces (w1, w0, x), (x, w0, w3): w0 has valence 4 and a
cone angle of 124 degrees (13 + 20 + 37.2 + 54.1; a sharp tip). Around the patch: rings of edge about E down a
body of revolution (a cone of length LC continued by a constant-curvature cap closed by a pole), ring
offsets and jitter from random.Random(SEED). The face order is the generation order (no shuffling).

What happens (old code, replayed flip by flip): the rim edge w3-w0 (facing 103 degrees at v) flips to v-x,
then the spoke v-w2 flips to w1-w3 (v: degree 3), then the rim edge w0-w1 (facing the 131-degree angle at v)
flips to a second edge v-x: w0 is left with degree 2, its two faces sharing both of its edges. The next flip,
of v-w0 (its two faces share the second edge w0-x), rebuilt the twin pairing by slot and corrupted it; one
more flip on the corrupted pairing removed w0 from every face, so w0 gets no heat and its distance is inf. Old binary (built with core/intrinsic_delaunay.cpp and core/heat_method.cpp of 0a200eb^), any source, e.g.
    cshapes geodesics centaur_fan_before_fix.off --source 0 --csv
    cshapes geodesics: error: geodesics (heat): the distance from vertex 0 to vertex 1 is inf although they
    are connected; the heat method failed numerically on this mesh; use --method fmm or exact, and please
    report the mesh                                                                    (exit status 1)
(the same with --source 1: "from vertex 1 to vertex 0 is inf", and --source 1431: "from vertex 1431 to vertex
1 is inf"). The fixed binary gives finite distances within 1.1% of the largest distance of --method exact
for those three sources.
Found by a seeded search over the fan's flex, the position of x, ring spacing and jitter (search seed 372).
"""
import math
import random
import sys

SEED = 372
E = 3.63
LC = 20.0
JITTER = 0.1
BETA = 63.397623625033305
X_OFFSET = (1.054989651482482, -0.8056527508193518, -0.39354067219121147)  # x - w0
# faces in cyclic order: (angle at v, angle at w_i, angle at w_{i+1})
FAN = [(131, 13, 36), (51, 114, 16), (43, 16, 121), (103, 57, 20)]


def rad(d):
    return math.radians(d)


def azim(p):
    return math.atan2(p[1], p[0]) % (2 * math.pi)


def spokes():
    s = [1.0]
    for at_v, at_wi, at_wn in FAN[:-1]:
        s.append(s[-1] * math.sin(rad(at_wi)) / math.sin(rad(at_wn)))
    sc = 1.26 / min(s)
    return [x * sc for x in s]


def flex_fan(beta_deg):
    """v at the origin, w0..w3 with the angles at v of FAN, the angle between spokes w1 and w3 equal to beta,
    rotated so that the mean spoke direction points down (-z)."""
    sp = spokes()
    A = [rad(f[0]) for f in FAN]
    b = rad(beta_deg)
    d1 = (1.0, 0.0, 0.0)

    def third(angle_to_1, angle_to_3, side):
        x = math.cos(angle_to_1)
        y = (math.cos(angle_to_3) - x * math.cos(b)) / math.sin(b)
        return (x, y, side * math.sqrt(1 - x * x - y * y))

    d3 = (math.cos(b), math.sin(b), 0.0)
    D = [third(A[0], A[3], -1), d1, third(A[1], A[2], 1), d3]
    m = [sum(d[i] for d in D) for i in range(3)]
    ln = math.sqrt(sum(x * x for x in m))
    m = [x / ln for x in m]
    t = (0.0, 0.0, -1.0)
    ax = (m[1] * t[2] - m[2] * t[1], m[2] * t[0] - m[0] * t[2], m[0] * t[1] - m[1] * t[0])
    s = math.sqrt(sum(x * x for x in ax))
    c = sum(x * y for x, y in zip(m, t))

    def rot(p):
        k = [x / s for x in ax]
        ang = math.atan2(s, c)
        kxp = (k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0])
        kp = sum(x * y for x, y in zip(k, p))
        return tuple(p[i] * math.cos(ang) + kxp[i] * math.sin(ang) + k[i] * kp * (1 - math.cos(ang)) for i in range(3))

    V = [(0.0, 0.0, 0.0)] + [rot(tuple(sp[i] * x for x in D[i])) for i in range(4)]
    return V, [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 1)]


def build():
    rng = random.Random(SEED)
    V, F = flex_fan(BETA)
    V = [list(p) for p in V]
    F = [list(t) for t in F]
    psi = math.acos(min(1, max(-1, -sum(V[i][2] / math.hypot(*V[i]) for i in range(1, 5)) / 4)))
    # x beside w0; w0's outside: (w1, w0, x), (x, w0, w3)
    V.append([V[1][0] + X_OFFSET[0], V[1][1] + X_OFFSET[1], V[1][2] + X_OFFSET[2]])
    F += [[2, 1, 5], [5, 1, 4]]
    # boundary loop of the patch (directed edges without a twin), then rings below it
    he = {}
    for t in F:
        for k in range(3):
            he[(t[k], t[(k + 1) % 3])] = 1
    bnd = [(a, b) for (a, b) in he if (b, a) not in he]
    nxt = dict(bnd)
    loop = [bnd[0][0]]
    while nxt[loop[-1]] != loop[0]:
        loop.append(nxt[loop[-1]])
    r0 = max(math.hypot(V[i][0], V[i][1]) for i in loop)
    z0 = min(V[i][2] for i in loop)
    k = math.cos(psi) / (r0 + LC * math.sin(psi))
    Ltot = LC + (psi + math.pi / 2) / k

    def prof(s):
        if s <= LC:
            return r0 + s * math.sin(psi), z0 - s * math.cos(psi)
        a = psi - k * (s - LC)
        return (r0 + LC * math.sin(psi) + (math.cos(a) - math.cos(psi)) / k,
                z0 - LC * math.cos(psi) - (math.sin(psi) - math.sin(a)) / k)

    rings = [sorted((azim(V[i]), i) for i in loop)]
    nr = max(2, int(round(Ltot / E)))
    for j in range(1, nr):
        r, z = prof(Ltot * j / nr)
        cnt = max(5, int(round(2 * math.pi * r / E)))
        off = rng.uniform(0, 2 * math.pi)
        R = []
        for q in range(cnt):
            t = off + 2 * math.pi * q / cnt + rng.uniform(-JITTER, JITTER) * 2 * math.pi / cnt
            rr = r * (1 + rng.uniform(-JITTER, JITTER) * E / max(r, E))
            V.append([rr * math.cos(t), rr * math.sin(t), z + rng.uniform(-JITTER, JITTER) * E])
            R.append((t % (2 * math.pi), len(V) - 1))
        rings.append(sorted(R))
    r, z = prof(Ltot)
    V.append([0.0, 0.0, z])
    pole = len(V) - 1
    # bands between consecutive rings, merged by azimuth (outward orientation)
    for A, B in zip(rings, rings[1:]):
        i = j = 0
        na, nb = len(A), len(B)
        while i < na or j < nb:
            a0, a1 = A[i % na], A[(i + 1) % na]
            b0, b1 = B[j % nb], B[(j + 1) % nb]
            next_a = A[(i + 1) % na][0] + (2 * math.pi if i + 1 >= na else 0)
            next_b = B[(j + 1) % nb][0] + (2 * math.pi if j + 1 >= nb else 0)
            if j >= nb or (i < na and next_a <= next_b):
                F.append([a0[1], b0[1], a1[1]])
                i += 1
            else:
                F.append([a0[1], b0[1], b1[1]])
                j += 1
    last = rings[-1]
    for q in range(len(last)):
        F.append([last[q][1], pole, last[(q + 1) % len(last)][1]])
    return V, F


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: make_centaur_fan_failing.py OUT.off")
    V, F = build()
    with open(sys.argv[1], "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        for p in V:
            f.write(f"{p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n")
        for t in F:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")


if __name__ == "__main__":
    main()
