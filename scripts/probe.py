#!/usr/bin/env python3
"""Replays issue 36's cases (crashes, silently wrong numbers, inputs overwritten), so that none comes back.

  scripts/probe.py [BUILD]     BUILD: the build folder (default build/)

The cases live in the test suite, which tests/run.sh runs whole; this runs only them, in seconds: the
GoogleTest cases named below (through CTest) and tests/python/test_trust.py. Exits non-zero on any failure.
Standard library only.
"""
import os
import subprocess
import sys

# The GoogleTest cases of the issue, each a test that failed before its fix.
CASES = [
    "OutputNotInput\\.",                      # no output may be an input (every command)
    "TrustCli\\.",                            # remesh at 1e±100, --resample, spectral failures, list options
    "TrustExperiments\\.",                    # paper, noise, pose, topkids say same content and --resample fallbacks
    "ScaleInvariance\\.",                     # every method's form at 1e-300 … 1e300
    "Geodesics\\.DistancesScaleWithTheMeshAtAnyFiniteScale",
    "ShapeDistance\\.AlignedDistanceScalesWithTheSetsAtAnyFiniteScale",
    "CanonicalFormsOfDegenerateInput\\.EveryErrorNamesTheMesh",
    "Remesh\\.(ExtremeScales|MeasuresHold)",  # remeshing and its measures at any scale
    "FormQuality\\.(ACollapsedForm|AReasonFromTheMethod)",
    "DiskCache\\.(AnEntryUnderAnotherKeysName|EntriesOfFormatTwo)",
    "Dataset\\.(TwoFilesOfTheSameContent|FolderEntriesThatAreNoMeshFile)",  # left out by name, the rest read
    "CanonicalFormsFromADistanceFile\\.AsymmetricMatrices",
    "CanonicalFormsMemory\\.",
    "CanonicalFormsThreads\\.",              # every method bit-identical at 1, 2 and 3 threads
    "CanonicalFormsScale\\.",                # far from unit size: a scaled copy, the same bits
    "ShapeFailures\\.AShapeFailingForSeveralMethods",
    "ExactGeodesics\\.AllPairsReportsEverySource",
    "DistanceMatrixFile\\.",
    "DistanceCsv\\.ANulByte",
    "OptionsKey\\.ExperimentsStartFromTheLibraryDefaults",
    "CliRefusals\\.OptionsOfAnotherMethod",
]


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build")
    regex = "^(" + "|".join(CASES) + ")"
    status = subprocess.call(["ctest", "--test-dir", build, "--output-on-failure", "-R", regex], cwd=root)
    interpreter_file = os.path.join(build, "python", "interpreter")
    interpreter = open(interpreter_file).read().strip() if os.path.exists(interpreter_file) else sys.executable
    env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"))
    status |= subprocess.call([interpreter, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                               os.path.join(root, "tests", "python", "test_trust.py")], cwd=root, env=env)
    return 1 if status else 0


if __name__ == "__main__":
    sys.exit(main())
