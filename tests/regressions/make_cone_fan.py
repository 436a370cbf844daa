#!/usr/bin/env python3
"""Writes cone_fan_valence4.off: the neighbourhood of the TOSCA centaur vertex of issue 21 inside a closed mesh.

The vertex has valence 4; its faces have the angles (13, 36, 131), (114, 16, 51), (121, 43, 16), (57, 20, 103)
degrees (in this cyclic order around it: the only order in which the four triangles close up, with the angles
131, 51, 43, 103 at the vertex: a cone point of 328 degrees) and edges 1.26-4.22 (spokes 3.29, 1.26, 4.17,
1.34 by the law of sines, scaled so that the shortest is 1.26). Around it: rings of vertices down a closed
cap of about the same mean edge (3.6), `rings` rings (22 for the committed file: `make_cone_fan.py cone_fan_valence4.off --rings 22`), closed by a pole. Deterministic for a seed.
Usage: make_cone_fan.py OUT.off [--seed S] [--rings R]
"""
import math
import random
import sys

def main():
    out = sys.argv[1]
    seed = int(sys.argv[sys.argv.index("--seed") + 1]) if "--seed" in sys.argv else 0
    rings = int(sys.argv[sys.argv.index("--rings") + 1]) if "--rings" in sys.argv else 12
    rng = random.Random(seed)
    rad = math.radians
    # faces in cyclic order: (angle at v, angle at w_i, angle at w_{i+1})
    fan = [(131, 13, 36), (51, 114, 16), (43, 121, 16), (103, 57, 20)]
    spokes = [1.0]
    for at_v, at_wi, at_wn in fan[:-1]:
        spokes.append(spokes[-1] * math.sin(rad(at_wi)) / math.sin(rad(at_wn)))
    scale = 1.26 / min(spokes)
    spokes = [s * scale for s in spokes]
    angles = [rad(f[0]) for f in fan]
    # Polar angle psi of a cone on which consecutive directions make exactly these angles and close up.
    def azimuth_gaps(psi):
        c2, s2 = math.cos(psi) ** 2, math.sin(psi) ** 2
        return [math.acos(max(-1.0, min(1.0, (math.cos(a) - c2) / s2))) for a in angles]
    lo, hi = max(angles) / 2 + 1e-9, math.pi / 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if sum(azimuth_gaps(mid)) > 2 * math.pi:
            lo = mid
        else:
            hi = mid
    psi = 0.5 * (lo + hi)
    gaps = azimuth_gaps(psi)
    V = [(0.0, 0.0, 0.0)]
    theta = 0.0
    ring1 = []
    for k in range(4):
        r = spokes[k]
        V.append((r * math.sin(psi) * math.cos(theta), r * math.sin(psi) * math.sin(theta), -r * math.cos(psi)))
        ring1.append((theta, len(V) - 1))
        theta += gaps[k]
    F = [(0, ring1[k][1], ring1[(k + 1) % 4][1]) for k in range(4)]
    # Rings down a sphere-like cap: ring j at polar angle phi_j on a sphere of radius R below the apex.
    R = 22.0
    edge = 3.6
    center_z = -R
    rings_list = [ring1]
    phi0 = math.atan2(max(math.hypot(p[0], p[1]) for p in V[1:]), 1.0)
    for j in range(1, rings):
        phi = phi0 + j * (math.pi - phi0) / rings
        rr = R * math.sin(phi)
        z = center_z + R * math.cos(phi)
        count = max(5, int(round(2 * math.pi * rr / edge)))
        offset = rng.uniform(0, 2 * math.pi)
        ring = []
        for k in range(count):
            t = offset + 2 * math.pi * k / count
            jr = rr * (1 + rng.uniform(-0.03, 0.03))
            V.append((jr * math.cos(t), jr * math.sin(t), z + rng.uniform(-0.3, 0.3)))
            ring.append((t % (2 * math.pi), len(V) - 1))
        ring.sort()
        rings_list.append(ring)
    V.append((0.0, 0.0, center_z - R))
    pole = len(V) - 1
    # Bands between consecutive rings, merged by azimuth (outward orientation: the apex looks up).
    for A, B in zip(rings_list, rings_list[1:]):
        A = sorted(A)
        B = sorted(B)
        i = j = 0
        na, nb = len(A), len(B)
        while i < na or j < nb:
            a0, a1 = A[i % na], A[(i + 1) % na]
            b0, b1 = B[j % nb], B[(j + 1) % nb]
            ta = A[i % na][0] + (2 * math.pi if i + 1 >= na else 0) if False else None
            next_a = A[(i + 1) % na][0] + (2 * math.pi if i + 1 >= na else 0)
            next_b = B[(j + 1) % nb][0] + (2 * math.pi if j + 1 >= nb else 0)
            if j >= nb or (i < na and next_a <= next_b):
                F.append((a0[1], b0[1], a1[1]))
                i += 1
            else:
                F.append((a0[1], b0[1], b1[1]))
                j += 1
    last = sorted(rings_list[-1])
    for k in range(len(last)):
        F.append((last[k][1], pole, last[(k + 1) % len(last)][1]))
    with open(out, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        for p in V:
            f.write(f"{p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n")
        for t in F:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")

if __name__ == "__main__":
    main()
