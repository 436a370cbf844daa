"""Minimal readers for the mesh files cshapes writes (OFF; PLY ascii / binary little- and big-endian),
returning vertices, faces and per-vertex properties. Plot scripts only; the C++ library does the real I/O."""
import numpy as np

_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_off(path):
    with open(path) as f:
        tokens = []
        for line in f:
            line = line.split("#", 1)[0]
            tokens.extend(line.split())
    if not tokens or not tokens[0].endswith("OFF"):
        raise ValueError(f"{path}: not an OFF file")
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = 4
    V = np.array(tokens[pos:pos + 3 * nv], dtype=float).reshape(nv, 3)
    pos += 3 * nv
    faces = []
    for _ in range(nf):
        k = int(tokens[pos])
        idx = [int(t) for t in tokens[pos + 1:pos + 1 + k]]
        pos += 1 + k
        faces.extend([idx[0], idx[j], idx[j + 1]] for j in range(1, k - 1))
    return V, np.array(faces, dtype=int).reshape(-1, 3), {}


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    header = data[:end].decode("ascii", "replace").splitlines()
    body = data[data.find(b"\n", end) + 1:]
    fmt, elements = "ascii", []
    for line in header:
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "format":
            fmt = parts[1]
        elif parts[0] == "element":
            elements.append([parts[1], int(parts[2]), []])
        elif parts[0] == "property":
            elements[-1][2].append(parts[1:])
    props, V, F = {}, np.zeros((0, 3)), np.zeros((0, 3), dtype=int)
    if fmt == "ascii":
        lines = body.decode().split("\n")
        row = 0
        for name, count, plist in elements:
            recs = [lines[row + i].split() for i in range(count)]
            row += count
            if name == "vertex":
                cols = {p[-1]: i for i, p in enumerate(plist)}
                arr = np.array(recs, dtype=float).reshape(count, len(plist))
                V = arr[:, [cols["x"], cols["y"], cols["z"]]]
                props = {k: arr[:, i] for k, i in cols.items() if k not in ("x", "y", "z")}
            elif name == "face":
                tris = []
                for r in recs:
                    k = int(r[0])
                    idx = [int(t) for t in r[1:1 + k]]
                    tris.extend([idx[0], idx[j], idx[j + 1]] for j in range(1, k - 1))
                F = np.array(tris, dtype=int).reshape(-1, 3)
        return V, F, props
    endian = "<" if fmt == "binary_little_endian" else ">"
    offset = 0
    for name, count, plist in elements:
        if all(p[0] != "list" for p in plist):
            dtype = np.dtype([(p[-1], endian + _PLY_TYPES[p[0]]) for p in plist])
            arr = np.frombuffer(body, dtype=dtype, count=count, offset=offset)
            offset += dtype.itemsize * count
            if name == "vertex":
                V = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(float)
                props = {k: arr[k].astype(float) for k in arr.dtype.names if k not in ("x", "y", "z")}
        else:  # faces: list count then indices (read record by record)
            tris = []
            for _ in range(count):
                for p in plist:
                    if p[0] == "list":
                        ct = np.dtype(endian + _PLY_TYPES[p[1]])
                        it = np.dtype(endian + _PLY_TYPES[p[2]])
                        k = int(np.frombuffer(body, ct, 1, offset)[0])
                        offset += ct.itemsize
                        idx = np.frombuffer(body, it, k, offset).astype(int)
                        offset += it.itemsize * k
                        if name == "face":
                            tris.extend([idx[0], idx[j], idx[j + 1]] for j in range(1, k - 1))
                    else:
                        offset += np.dtype(_PLY_TYPES[p[0]]).itemsize
            if name == "face":
                F = np.array(tris, dtype=int).reshape(-1, 3)
    return V, F, props


def read_mesh(path):
    lower = path.lower()
    if lower.endswith(".off"):
        return read_off(path)
    if lower.endswith(".ply"):
        return read_ply(path)
    if lower.endswith(".xyz"):
        V = np.loadtxt(path, ndmin=2)[:, :3]
        return V, np.zeros((0, 3), dtype=int), {}
    raise ValueError(f"{path}: unsupported format for plotting (use .off, .ply or .xyz)")
