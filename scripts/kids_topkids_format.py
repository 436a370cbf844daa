#!/usr/bin/env python3
"""A TOPKIDS-format point-map set from KIDS poses (one triangulation of 59,727 vertices in every pose), so
that `cshapes experiment topkids` can score maps on data that is not TOPKIDS (the tuning half of a split).

Each pose is re-triangulated on its own (a different triangulation per pose, as in a scanned collection):
  --decimate N   quadric edge collapse (Open3D) to about N vertices: uneven, scan-like triangles;
  --remeshed DIR take DIR/kidK.off (e.g. the resampled/ folder of `experiment pose --resample N`).
--glued DIR takes each query's mesh from DIR/kidK_glue4.off instead (`experiment noise` shapes/: the same
vertices with glued tubes). The reference is pose --reference (kid00.off); every other pose K is a query
kidKK.off with kidKK_ref.txt (query vertex -> the reference vertex at the same body point: the nearest
original vertex, the same index on the reference pose, the nearest re-triangulated reference vertex) and
kidKK_sym.txt (query vertex -> its left-right mirror on the query; KIDS's null pose kid0 is symmetric under
x -> -x, which gives the triangulation's mirror map).

usage: kids_topkids_format.py OUT --poses 0,1,...,7 (--decimate N | --remeshed DIR) [--glued DIR]
       [--kids ../shared/data/kids]   (Debian: python3-numpy, python3-scipy; --decimate: python3-open3d)
"""
import argparse, os, shutil, sys
import numpy as np
from scipy.spatial import cKDTree


def read_off(path):
    with open(path) as f:
        if f.readline().strip() != 'OFF':
            sys.exit(f'{path}: not an OFF file')
        n, m, _ = map(int, f.readline().split())
        V = np.loadtxt(f, max_rows=n)
        F = np.loadtxt(f, max_rows=m, dtype=np.int64)[:, 1:4]
    return V, F


def write_off(path, V, F):
    with open(path, 'w') as f:
        f.write(f'OFF\n{len(V)} {len(F)} 0\n')
        np.savetxt(f, V, fmt='%.9g')
        np.savetxt(f, np.c_[np.full(len(F), 3), F], fmt='%d')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('out')
    ap.add_argument('--poses', default='0,1,2,3,4,5,6,7')
    ap.add_argument('--reference', type=int, default=0)
    ap.add_argument('--kids', default=os.environ.get('CSHAPES_DATA', '../shared/data') + '/kids')
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument('--decimate', type=int)
    g.add_argument('--remeshed')
    ap.add_argument('--glued')
    a = ap.parse_args()
    poses = [int(p) for p in a.poses.split(',')]
    if a.reference not in poses:
        sys.exit(f'--reference {a.reference} is not among --poses {a.poses}')
    os.makedirs(a.out, exist_ok=True)
    original = {k: read_off(f'{a.kids}/kid{k}.off')[0] for k in poses + [0]}
    mesh = {}
    for k in poses:
        if a.decimate:
            import open3d as o3d
            m = o3d.io.read_triangle_mesh(f'{a.kids}/kid{k}.off')
            d = m.simplify_quadric_decimation(target_number_of_triangles=2 * a.decimate)
            d.remove_unreferenced_vertices()
            # rounded as the OFF file stores them, so that the maps are those of the files written
            V = np.char.mod('%.9g', np.asarray(d.vertices)).astype(float)
            mesh[k] = (V, np.asarray(d.triangles))
        else:
            mesh[k] = read_off(f'{a.remeshed}/kid{k}.off')
    reflected = original[0].copy()
    reflected[:, 0] = -reflected[:, 0]
    distance, mirror = cKDTree(original[0]).query(reflected)
    diagonal = np.linalg.norm(original[0].max(0) - original[0].min(0))
    if np.percentile(distance, 99) > 1e-4 * diagonal:
        sys.exit('kid0 is not symmetric under x -> -x: no mirror map')
    ref_V, ref_F = mesh[a.reference]
    write_off(f'{a.out}/kid00.off', ref_V, ref_F)
    ref_tree = cKDTree(ref_V)
    for k in poses:
        if k == a.reference:
            continue
        V, F = mesh[k]
        _, nearest = cKDTree(original[k]).query(V)
        _, truth = ref_tree.query(original[a.reference][nearest])
        _, mirrored = cKDTree(V).query(original[k][mirror[nearest]])
        name = f'kid{k:02d}'
        if a.glued:
            GV, GF = read_off(f'{a.glued}/kid{k}_glue4.off')
            if len(GV) != len(V) or np.abs(GV - V).max() > 0:
                sys.exit(f'{a.glued}/kid{k}_glue4.off: not the vertices of pose {k}')
            V, F = GV, GF
        write_off(f'{a.out}/{name}.off', V, F)
        np.savetxt(f'{a.out}/{name}_ref.txt', np.c_[np.arange(1, len(V) + 1), truth + 1], fmt='%6d')
        np.savetxt(f'{a.out}/{name}_sym.txt', np.c_[np.arange(1, len(V) + 1), mirrored + 1], fmt='%6d')
        print(f'{name}: {len(V)} vertices')


if __name__ == '__main__':
    main()
