"""The prose of the Python functions' documentation (cshapes/_api.py renders it in numpy style): each function's
summary, description, Returns, Raises and Examples, and the descriptions of the parameters that are neither a
canonical-form method's option nor a keyword with a CLI counterpart (those come from the options' own
declarations in the library: cshapes.method_options(), cshapes.option_declarations()). A parameter several functions
share is described once, in COMMON. Text for people: keywords as Python spells them, never the CLI's flags
(tests/python/test_api.py)."""

# Parameters several functions share, described once.
COMMON = {
    "V": "(n, 3) vertex coordinates, any real dtype and strides (copied once into the library's layout).",
    "F": "(m, 3) vertex indices of the triangles, any integer dtype; an empty (0, 3) array or None: a point "
         "cloud, joined by its k-nearest-neighbour graph.",
    "knn": "Point clouds (no faces) only: the neighbours each point is joined to in the graph that stands in for "
           "the edges. Given with faces, it is refused.",
    "progress": "Reports while the call runs. None: on a terminal, the bar once the call has run for a second "
                "(a quicker call prints nothing); elsewhere (a log, a notebook) nothing. "
                "True: the bar, always: one line rewritten in place, ``[stage]  42.0% (about 12 s left)``. "
                "False: nothing. A function ``progress(stage, fraction, seconds_left)``: called with the stage's "
                "name (str), the fraction done (0..1, never decreasing within a stage) and the seconds it has "
                "left (None until an estimate means something), at most about ten times a second, from the "
                "computing thread with the GIL held. An exception it raises stops the call and is raised by it.",
    "methods": "The canonical-form methods: a list of names (``['coulomb', 'lbo']``), one string of "
               "comma-separated names, or methods from outside: ``'NAME=cmd:COMMAND'``, "
               "``'NAME=forms:DIR'``, or a pair ``(NAME, fn)`` with ``fn(V, F) -> X`` (n, 3), one row per "
               "vertex of V in V's order (docs/outside-methods.md). None: every registered method.",
    "seed": "The seed of every random choice: the same seed, the same result.",
    "D": "(n, n) distance matrix, any real dtype: symmetric, zero diagonal.",
}

_CANONICAL_FORM_RETURNS = (
    "CanonicalForm\n"
    "    ``X`` (n, 3) in the input's vertex order and units (NaN rows where ``valid`` is 0: vertices a repair "
    "dropped), ``valid`` (n,), ``torn`` (n,) 1 at vertices of torn edges (coulomb) or None, ``history`` "
    "{column: (iterations,) array} (energy, mean_violation, ... per iteration), ``iterations``, ``summary`` "
    "(the dict the CLI's ``cshapes canon`` prints as JSON; spectral methods: eigenvalues, near_multiple, ...), "
    "``seconds``, ``method``.")

_EXPERIMENT_RAISES = (
    "ValueError\n    A dataset, method or option the run cannot use, named with what was expected.\n"
    "OSError\n    A file that cannot be read or written.\n"
    "KeyboardInterrupt\n    Ctrl-C: the run stops within about a second; what it finished stays cached.")

DOCS = {
    "read_mesh": dict(
        summary="Read a mesh or point cloud: .off, .ply, .obj, .stl, .vert/.tri (TOSCA), .xyz.",
        description="Reading is lenient: only malformed files are refused. Defects a real mesh may have "
                    "(non-manifold edges, duplicate faces, several components) are described by mesh_info().",
        params={"path": "The file; its extension names the format.",
                "fields": "Also return PLY's other per-vertex properties."},
        returns="(V, F) or (V, F, fields)\n    V (n, 3) float64 in the file's units, F (m, 3) int32 vertex "
                "indices, 0-based ((0, 3) for a point cloud); with fields=True, a dict of 1-D float64 arrays "
                "(and 'colors', (n, 3) uint8).",
        raises="ValueError\n    A malformed file, naming the file and the line or element.\n"
               "OSError\n    A file that cannot be opened.",
        examples=">>> V, F = cshapes.read_mesh('cat0.off')\n>>> V.shape, F.shape\n((27894, 3), (55784, 3))"),
    "write_mesh": dict(
        summary="Write V and F by the path's extension (.off, .ply, .obj, .xyz), atomically.",
        description="Reading the file back gives exactly the same V (17 significant digits). Coordinates must "
                    "be finite, except in PLY rows whose 'valid' field is 0.",
        params={"path": "The file to write; its extension names the format.",
                "binary": "Write binary little-endian PLY.",
                "vertex_fields": "Per-vertex fields, each (n,), written as PLY double properties (.ply only)."},
        returns="None",
        raises="ValueError\n    Arrays of the wrong shape, non-finite coordinates, fields for another format.\n"
               "OSError\n    A file that cannot be written.",
        examples=">>> form = cshapes.coulomb(V, F)\n>>> cshapes.write_mesh('cat0-coulomb.ply', form.X, F, "
                 "torn=form.torn)"),
    "mesh_info": dict(
        summary="Counts, topology, size and defects of a mesh: the dict the CLI's ``cshapes info`` prints as "
                "JSON.",
        returns="dict\n    vertices, faces, edges, components, isolated_vertices, boundary_edges, boundary_loops, "
                "nonmanifold_edges, euler_characteristic, genus (-1 when undefined), bbox_diagonal, "
                "mean_edge_length, area (mesh units), and defects: {summary, any, nonmanifold_edges: {count, "
                "examples}, nonmanifold_vertices, isolated_vertices, duplicate_faces, repeated_vertex_faces, "
                "zero_area_faces, zero_length_edges, components, component_sizes, boundary_edges, "
                "boundary_loops}.",
        raises="ValueError\n    Arrays of the wrong shape, NaN coordinates, face indices out of range.",
        examples=">>> V, F = cshapes.generate('icosphere', subdivisions=2)\n>>> cshapes.mesh_info(V, F)['genus']\n0"),
    "geodesics": dict(
        summary="Geodesic distances on a triangle mesh, in mesh units.",
        description="A mesh that is not one manifold component is repaired first (a warning says what) and the "
                    "distances are given at the input's vertices: NaN where a vertex was dropped.",
        params={"sources": "None: all pairs, (n, n) float32 as the library stores them (n² × 4 bytes); a vertex "
                           "index: one row (n,) float64; a sequence of k indices: (k, n) float64, row r from "
                           "sources[r]."},
        returns="numpy.ndarray\n    (n,), (k, n) or (n, n), as sources asks.",
        raises="ValueError\n    A source that is not a vertex index, heat_mode with another method, a mesh "
               "refused by strict=True.\nKeyboardInterrupt\n    Ctrl-C, heard every 64 sources.",
        examples=">>> V, F = cshapes.generate('icosphere', subdivisions=3)\n"
                 ">>> d = cshapes.geodesics(V, F, 0, method='exact')\n>>> round(float(d.max()), 2)  # about π: half "
                 "a great circle\n3.13"),
    "add_topological_noise": dict(
        summary="Topological noise the paper's way: glue almost-touching spots by short tubes "
                "(``cshapes noise``).",
        description="The vertices stay the same; each glue adds a handle. The input must be one manifold "
                    "component.",
        params={"return_info": "Also return what was glued."},
        returns="(V, F) or (V, F, info)\n    The glued mesh; info: the glued pairs, the tubes' rims and their "
                "distances.",
        raises="ValueError\n    Fewer admissible pairs than glue (saying how many were found), or a mesh that "
               "is not one manifold component.",
        examples=">>> (V, F), = cshapes.generate('articulated', class_='hand', poses=1, vertices=3000)\n"
                 ">>> V2, F2 = cshapes.add_topological_noise(V, F, glue=2, seed=1)"),
    "generate": dict(
        summary="Shapes made here, deterministic for a seed (``cshapes generate``).",
        description="kind='swissroll' -> (V, F), the Swiss roll of Table 1; 'icosphere' -> (V, F); "
                    "'articulated' -> [(V, F), ...], poses of one synthetic class with the same faces and vertex "
                    "order; 'hand' -> {'separated': (V, F), 'glued': (V, F), 'glued_pairs': [...]}; 'dataset' "
                    "-> [{'name', 'class', 'pose', 'noisy', 'V', 'F', 'glued_pairs'}, ...]. Each kind reads "
                    "its own keywords and refuses the others. The CLI writes these shapes as OFF with 6 "
                    "decimals; these arrays are not rounded.",
        params={"kind": "'swissroll', 'icosphere', 'articulated', 'hand' or 'dataset'.",
                "vertices": "About this many vertices per shape.",
                "subdivisions": "Loop subdivisions of the icosahedron, 0..8.",
                "radius": "The sphere's radius (> 0).",
                "class_": "The synthetic class.",
                "poses": "Poses per class.",
                "amplitude": "How far the poses bend, 1: the default range of each joint.",
                "glue": "Glued places (hand: fingers glued; dataset: per noisy shape).",
                "classes": "Classes of the dataset.",
                "noisy": "Noisy (glued) shapes per class."},
        returns="(V, F), list or dict\n    As kind says above.",
        raises="ValueError\n    An unknown kind, or a keyword outside its limit.\nTypeError\n    A keyword the kind "
               "does not read.",
        examples=">>> V, F = cshapes.generate('icosphere', subdivisions=1)\n>>> V.shape\n(42, 3)"),
    "canonical_form_methods": dict(
        summary="The methods canonical_form() takes, in the library's order.",
        returns="list of dict\n    {name, title, summary, uses_geodesic_matrix, keywords}: name is what method= "
                "takes, title the method's name in figures and tables ('Coulomb', 'classical MDS', 'SMACOF'), "
                "keywords the options it reads (besides knn and strict).",
        examples=">>> [m['name'] for m in cshapes.canonical_form_methods()][:3]\n['coulomb', 'cmds', 'smacof']"),
    "option_declarations": dict(
        summary="The keywords each function shares with a CLI option, declared once in the library: what the "
                "CLI's help and this documentation are made from.",
        returns="dict\n    {function: [{keyword, flag, help, cli_help, limit, choices}, ...]}: keyword as the "
                "function takes it, flag the CLI's option, help as this documentation gives it, cli_help as the "
                "CLI's help shows it, limit in words ('a number in [0, 0.9]') or None, choices the names a "
                "choice takes.",
        examples=">>> [o['keyword'] for o in cshapes.option_declarations()['icp']][:2]\n"
                 "['no_reflections', 'one_way']"),
    "method_options": dict(
        summary="Every option of the registered methods, once each: what the CLI, this documentation and the "
                "stub are made from.",
        returns="list of dict\n    {name, flag, type ('int', 'float', 'str'), default, choices, limit, help, "
                "methods}: name is the keyword of canonical_form(), flag the CLI's option, methods the methods "
                "that read it.",
        examples=">>> {o['name']: o['default'] for o in cshapes.method_options()}['eigenpairs']\n10"),
    "coulomb": dict(
        summary="The Coulomb canonical form of a mesh (the paper's §2): electrostatic repulsion under "
                "edge-length constraints.",
        description="A mesh with several components or other defects is repaired for the method first "
                    "(summary['repair'] says what); dropped vertices are NaN rows with valid = 0. The same as "
                    "canonical_form(V, F, method='coulomb', ...).",
        returns=_CANONICAL_FORM_RETURNS,
        raises="ValueError\n    Bad arrays, a keyword outside its limit, a keyword given where it does not "
               "apply (fixed_step without step_rule='fixed'), a mesh refused by strict=True.\nTypeError\n    "
               "An unknown keyword (an old name is answered with the new one).\nKeyboardInterrupt\n    Ctrl-C, "
               "heard at each iteration.",
        examples=">>> (V, F), = cshapes.generate('articulated', class_='hand', poses=1, vertices=3000)\n"
                 ">>> form = cshapes.coulomb(V, F, progress=False)\n>>> form\n"
                 "<cshapes.CanonicalForm: coulomb, 3,000 points, 480 iterations, 0.959 s>"),
    "canonical_form": dict(
        summary="A canonical form by any method, as the CLI's ``cshapes canon`` computes it.",
        description="Each method reads its own keywords and refuses the others, naming the methods that read "
                    "them; every method reads knn and strict. method may also be a method from outside "
                    "(docs/outside-methods.md): a function ``fn(V, F) -> X`` ((n, 3), one row per vertex), a "
                    "pair (name, fn), 'NAME=cmd:COMMAND' or 'NAME=forms:DIR', which read method_timeout and "
                    "method_version; its form is checked as an experiment checks it (one finite row per vertex, "
                    "spanning a plane) and gets the same quality verdict.",
        params={"method": "A registered method (canonical_form_methods(): 'coulomb', 'cmds', 'smacof', 'lbo', "
                          "'diffusion', 'spectral-mds', ...) or a method from outside (see above)."},
        returns=_CANONICAL_FORM_RETURNS,
        raises="ValueError\n    Bad arrays, an unknown method, a keyword outside its limit or given where it "
               "does not apply, a mesh refused by strict=True.\nTypeError\n    A keyword the method does not "
               "read (naming the methods that do), an unknown or old keyword (naming the new one), or options "
               "given by position.\nKeyboardInterrupt\n    Ctrl-C, heard at each iteration.",
        examples=">>> V, F = cshapes.read_mesh('cat0.off')\n"
                 ">>> form = cshapes.canonical_form(V, F, method='lbo', eigenpairs=12)\n"
                 ">>> cshapes.show(V, form, out='cat0-lbo.png')"),
    "classical_mds": dict(
        summary="Classical MDS of an (n, n) distance matrix.",
        params={"dim": "The embedding's dimension, 1..3: the leading axes of the 3-D embedding."},
        returns="CanonicalForm\n    X (n, dim), centred, in the units of D; summary['classical_mds']: "
                "eigenvalues, most_negative_eigenvalue, explained_energy, ...",
        raises="ValueError\n    D not square, not finite, or dim outside 1..3.",
        examples=">>> D = cshapes.geodesics(V, F).astype(float)\n>>> form = cshapes.classical_mds(D)"),
    "smacof": dict(
        summary="SMACOF metric MDS of an (n, n) distance matrix (stored as float32, as the library keeps them).",
        params={"X0": "(n, 3) start; None starts from classical MDS of D.",
                "weights": "None (uniform) or n positive vertex weights (pair weights w_i w_j)."},
        returns="CanonicalForm\n    X (n, 3), history (passes, normalized_stress, extrapolated per iteration), "
                "iterations, summary['smacof'] {normalized_stress, stop_reason, ...}.",
        raises="ValueError\n    D not square or not finite, a keyword outside its limit.",
        examples=">>> form = cshapes.smacof(D, smacof_max_iterations=100)\n"
                 ">>> form.summary['smacof']['stop_reason']"),
    "icp": dict(
        summary="Rigid ICP alignment of point set A onto B, as ``cshapes align`` does it.",
        description="Starts from the matched principal axes (every sign, reflections included) and the input "
                    "pose, coarse to fine.",
        params={"A": "(n, 3) points, moved.", "B": "(k, 3) points, fixed."},
        returns="Alignment\n    R, t (B ≈ A @ R.T + t), transform (4, 4), aligned (A moved), reflection, and the "
                "distances after it in the inputs' units: hausdorff (the paper's), chamfer, rmse, with the "
                "correspondences.",
        raises="ValueError\n    Arrays of the wrong shape or not finite, a keyword outside its limit.",
        examples=">>> poses = cshapes.generate('articulated', class_='hand', poses=2, vertices=3000)\n"
                 ">>> form0, form1 = (cshapes.coulomb(V, F) for V, F in poses)\n"
                 ">>> cshapes.icp(form1.X, form0.X)\n<cshapes.Alignment: hausdorff 5.53 (2.74% of B's bbox "
                 "diagonal), rmse 0.949 (0.471%) in the inputs' units, 69 ICP iterations>"),
    "shape_distance": dict(
        summary="Distance between two point sets after ICP (align=True, the paper's) or as given.",
        description="Rows with NaN (vertices dropped by a repair) are left out.",
        params={"A": "(n, 3) points.", "B": "(k, 3) points.",
                "kind": "'hausdorff' (the largest nearest-neighbour distance, the paper's), 'chamfer' (the "
                        "mean), 'rmse'.",
                "align": "Align A onto B by ICP first; False: the distance as given (the ICP keywords are then "
                         "refused)."},
        returns="float\n    In the inputs' units.",
        raises="ValueError\n    An unknown kind, ICP keywords with align=False.",
        examples=">>> cshapes.shape_distance(form1.X, form0.X, kind='chamfer')"),
    "distance_matrix": dict(
        summary="The all-pairs distance matrix of canonical forms: ICP between every pair, then the distance "
                "(``cshapes distmat``).",
        description="The pairs run in parallel with the GIL released.",
        params={"forms": "(n_i, 3) arrays or CanonicalForm objects (their X; NaN rows are left out), at least 2.",
                "cache": "A folder where each pair's result is kept: a rerun, or a killed run restarted, "
                         "recomputes nothing cached. None: no cache.",
                "threads": "Threads for the pairs; 0: OpenMP's default."},
        returns="numpy.ndarray\n    (N, N) float64, symmetric, zero diagonal, in the forms' units.",
        raises="ValueError\n    Fewer than two forms, an unknown metric, a keyword outside its limit.\n"
               "KeyboardInterrupt\n    Ctrl-C, heard between pairs and in each.",
        examples=">>> forms = [cshapes.coulomb(V, F) for V, F in shapes]\n"
                 ">>> D = cshapes.distance_matrix(forms, progress=True)"),
    "retrieval_measures": dict(
        summary="Retrieval measures of an (N, N) distance matrix with one class label per shape: the dict "
                "``cshapes evaluate`` writes to metrics.json.",
        description="Queries from classes smaller than min_class_size are skipped. Ties (exactly equal "
                    "distances) count as evaluate counts them: every measure is its expected value over all "
                    "orders of the tied shapes.",
        params={"D": "(N, N) distances.", "labels": "One class label per shape (any hashable, as text; 1 and "
                "1.0 are one class).", "names": "Shape names for the report; None: 0..N-1."},
        returns="dict\n    map, nn, ft, st, e, dcg (micro averages over queries, psbTable conventions), pr "
                "{recall, precision}, classes {name: per-class measures}, queries, skipped, tied_queries, "
                "confusion, class_names.",
        raises="ValueError\n    Labels or names of the wrong count, non-finite or negative distances, all "
               "labels equal.",
        examples=">>> m = cshapes.retrieval_measures(D, ['cat', 'cat', 'dog', 'dog'], min_class_size=2)\n"
                 ">>> m['map']"),
    "experiment_paper": dict(
        summary="The paper's experiment end to end (``cshapes experiment paper``).",
        description="Writes what the CLI writes (metrics.json, distances/, canon/, report.md, ...); the same "
                    "options give the same files as the CLI and C++.",
        params={"poses_per_class": "Clean poses per class; 0: all.",
                "noisy_per_class": "Glued versions per class; -1: one of every clean pose."},
        returns="dict\n    out, shapes, seconds, canonical_forms_computed, canonical_forms_cached, "
                "pairs_computed, pairs_cached, figures_drawn, failures.",
        raises=_EXPERIMENT_RAISES,
        examples=">>> cshapes.experiment_paper('data/synthetic', 'out/paper', methods=['coulomb', 'cmds'], "
                 "table1=False)"),
    "experiment_retrieval": dict(
        summary="A whole collection as a retrieval benchmark (``cshapes experiment retrieval``).",
        description="Writes what the CLI writes (report.md, retrieval.json, METHOD/DISTANCE.csv, classes.cla, "
                    "...).",
        returns="dict\n    out, shapes, classes, seconds, resampled, measures {method: {distance: {map, nn, ft, "
                "st, e, dcg}}}, figures, failures; with two_stage_k > 0, two_stage {method: {k, pairs_aligned, "
                "recall_at_k and exact {distance: measures} when two_stage_reference is given}}.",
        raises=_EXPERIMENT_RAISES,
        examples=">>> r = cshapes.experiment_retrieval('data/tosca', 'out/tosca', methods='coulomb,lbo')\n"
                 ">>> r['measures']['coulomb']['hausdorff']['map']"),
    "experiment_noise": dict(
        summary="Retrieval under topological noise (``cshapes experiment noise``): glued versions of every "
                "clean pose.",
        params={"poses_per_class": "Clean poses per class; 0: all."},
        returns="dict\n    out, results (the run's noise.json), failures.",
        raises=_EXPERIMENT_RAISES,
        examples=">>> cshapes.experiment_noise('data/synthetic', 'out/noise', methods=['coulomb'], levels=[0, 2])"),
    "experiment_pose": dict(
        summary="Pose residuals against ground-truth correspondence, per part (``cshapes experiment pose``).",
        returns="dict\n    out, results (the run's pose_residuals.json), failures.",
        raises=_EXPERIMENT_RAISES,
        examples=">>> cshapes.experiment_pose('data/synthetic', 'out/pose', methods=['coulomb', 'lbo'])"),
    "experiment_topkids": dict(
        summary="SHREC'16 TOPKIDS correspondence curves (``cshapes experiment topkids``).",
        returns="dict\n    out, results (the run's topkids.json), failures.",
        raises=_EXPERIMENT_RAISES,
        examples=">>> cshapes.experiment_topkids('data/topkids', 'out/topkids', methods=['coulomb'])"),
    "experiment_invariance": dict(
        summary="How much each canonical form changes under transformations that must not change it "
                "(``cshapes experiment invariance``).",
        description="Vertex renumbering, face order, rigid motion, scale 1e-6 and 1e3, jitter of 1e-9 of the "
                    "diagonal, and, reported apart, remeshing at 0.8x and 1.2x the vertex count; beside each "
                    "method's pose variation, with a verdict per method. Writes invariance.md, .csv, "
                    "_summary.csv, _pose.csv, .json and the figure.",
        returns="dict\n    out, results (invariance.json: verdicts, summary, ...), failures.",
        raises=_EXPERIMENT_RAISES,
        examples=">>> cshapes.experiment_invariance('data/synthetic', 'out/inv', methods=['coulomb'], seeds=2)"),
    "compare_runs": dict(
        summary="Several ``experiment_retrieval`` runs on the same data side by side (``cshapes compare``), "
                "nothing recomputed.",
        description="A method in two runs must have the same results in both. Anything else raises ValueError "
                    "naming the folder and what was expected, and writes nothing.",
        params={"runs": "Two or more output folders of complete runs on the same inputs (their checksums in "
                        "retrieval.json agree), under the same protocol."},
        returns="dict\n    experiment, inputs_digest, shapes, measures {method: {distance: {...}}}, runs "
                "{method: the folder its numbers come from}, figures.",
        raises="ValueError\n    Runs that cannot be compared, naming the folder.",
        examples=">>> cshapes.compare_runs(['out/a', 'out/b'], 'out/compare')"),
    "show": dict(
        summary="A picture of a mesh, or of a mesh and its canonical form side by side (``cshapes show``).",
        description="Each vertex takes the same colour in both panels: its place on the mesh (principal "
                    "coordinates as red, green and blue). Each panel is titled: a form by its method when that "
                    "is known, a file by its name, else 'mesh' and 'canonical form'. Needs a Python with "
                    "matplotlib and numpy (/usr/bin/python3, $CSHAPES_PYTHON).",
        params={"mesh": "A file in any format cshapes reads, a CanonicalForm, a (V, F) pair or an (n, 3) array "
                        "(a point cloud).",
                "form": "The same kinds, with the mesh's vertex count (an array is drawn with the mesh's "
                        "faces); None: the mesh alone. NaN rows are not drawn.",
                "out": "The picture, .png, .pdf or .svg (without an extension: figure_format's; with one, "
                       "figure_format must agree), never one of the inputs; written atomically.",
                "labels": "Panel titles instead: [mesh's] or [mesh's, form's]."},
        returns="str\n    The picture's path.",
        raises="ValueError\n    Inputs that do not match, or why it cannot draw.",
        examples=">>> cshapes.show('cat0.obj', cshapes.coulomb(V, F), out='cat0.pdf')"),
    "set_num_threads": dict(
        summary="OpenMP threads of every later call, from any Python thread.",
        params={"n": "Threads; 0: the default (OMP_NUM_THREADS or all cores)."},
        returns="None", examples=">>> cshapes.set_num_threads(1)"),
    "get_num_threads": dict(summary="OpenMP threads later calls use.", returns="int",
                            examples=">>> cshapes.get_num_threads()"),
    "build_info": dict(
        summary="What this module is: its version, build and the kernels' instruction set.",
        returns="dict\n    version, build, simd (the instruction set the kernels run with: the best this CPU "
                "supports, or CSHAPES_SIMD=baseline|avx2|avx512 read at the first call), simd_supported.",
        examples=">>> cshapes.build_info()['version'] == cshapes.__version__\nTrue"),
}
