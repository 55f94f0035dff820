#!/usr/bin/env python3
"""The layer check (tools/ci/check_layers.py) fails on each kind of violation it exists for.

A copy of the tree's code is checked as it is (it must pass), then with one violation planted at a time: each must
make the check exit 1 with a line naming the planted file (and line). Usage: test_check_layers.py ROOT.
"""
import pathlib
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(sys.argv[1]).resolve()
CHECK = ROOT / "tools" / "ci" / "check_layers.py"
CODE = ["CMakeLists.txt", "io", "core", "methods", "eval", "sweeps", "tools", "tests", "bench", "examples"]


def skip(folder, names):
    """Only code and CMake files are copied: no build folder, test data, corpora or docs."""
    here = pathlib.Path(folder)
    return [n for n in names if n in ("build", "corpus") or (n == "data" and here.name == "tests")
            or (here / n).is_file() and not n.endswith((".hpp", ".cpp", ".h", ".txt", ".in"))]


def check(tree):
    r = subprocess.run([sys.executable, str(CHECK), str(tree)], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


def plant(tree, rel, text, where):
    """Adds `text` to file `rel` (at the top or the end); returns the original content."""
    f = tree / rel
    old = f.read_text() if f.exists() else None
    f.parent.mkdir(parents=True, exist_ok=True)
    f.write_text(text + (old or "") if where == "top" else (old or "") + text)
    return old


def restore(tree, rel, old):
    f = tree / rel
    f.unlink() if old is None else f.write_text(old)


CASES = [
    # (what, file, planted text, where, what the message must name)
    ("core includes a sweeps header", "core/include/occsweep/core/log_odds.hpp",
     '#include "occsweep/sweeps/grid.hpp"\n', "top", "core/include/occsweep/core/log_odds.hpp:1: core includes"),
    ("core includes a method (core knows no method)", "core/include/occsweep/core/mapping_method.hpp",
     '#include "occsweep/methods/knn/knn_method.hpp"\n', "top",
     "core/include/occsweep/core/mapping_method.hpp:1: core includes"),
    ("the engine includes a method (it needs only the contract)", "sweeps/engine/src/replay.cpp",
     '#include "occsweep/methods/octomap/octomap_baseline.hpp"\n', "top",
     "sweeps/engine/src/replay.cpp:1: engine includes"),
    ("a method includes the data-set model", "methods/knn/include/occsweep/methods/knn/knn_method.hpp",
     '#include "occsweep/eval/dataset.hpp"\n', "top",
     "methods/knn/include/occsweep/methods/knn/knn_method.hpp:1: methods includes"),
    ("a core test includes a method", "tests/core/test_ray_traversal.cpp",
     '#include "occsweep/methods/knn/knn_method.hpp"\n', "top",
     "tests/core/test_ray_traversal.cpp:1: tests/core includes"),
    ("methods leaves a source unlisted", "methods/knn/src/unlisted.cpp",
     "int unlisted = 0;\n", "end", "does not list methods/knn/src/unlisted.cpp"),
    ("io includes the data-set model (io knows no data set)", "io/src/output_file.cpp",
     '#include "occsweep/eval/dataset.hpp"\n', "top", "io/src/output_file.cpp:1: io includes"),
    ("io includes core", "io/src/ownership.cpp",
     '#include "occsweep/core/limits.hpp"\n', "top", "io/src/ownership.cpp:1: io includes"),
    ("eval includes an importer", "eval/src/dataset_io.cpp",
     '#include "occsweep/data/import_cloud.hpp"\n', "top", "eval/src/dataset_io.cpp:1: eval includes"),
    ("results includes the engine", "sweeps/results/src/merge.cpp",
     '#include "occsweep/sweeps/sweep.hpp"\n', "top", "sweeps/results/src/merge.cpp:1: results includes"),
    ("cluster includes reproduce (sideways)", "sweeps/cluster/src/cluster_plan.cpp",
     '#include "occsweep/sweeps/reproduce.hpp"\n', "top", "sweeps/cluster/src/cluster_plan.cpp:1: cluster includes"),
    ("a method test includes eval", "tests/methods/test_mappers.cpp",
     '#include "occsweep/eval/confusion.hpp"\n', "top", "tests/methods/test_mappers.cpp:1: tests/methods includes"),
    ("grid links reproduce", "sweeps/grid/CMakeLists.txt",
     "target_link_libraries(occsweep_grid PUBLIC occsweep::reproduce)\n", "end", "grid links occsweep::reproduce"),
    ("a part leaves a source unlisted", "sweeps/engine/src/unlisted.cpp",
     "int unlisted = 0;\n", "end", "does not list sweeps/engine/src/unlisted.cpp"),
    ("the command line leaves a subcommand unlisted", "tools/occsweep/cmd_unlisted.cpp",
     "int unlisted = 0;\n", "end", "does not list tools/occsweep/cmd_unlisted.cpp in occsweep_cli"),
    ("map includes the engine", "tools/occsweep/cmd_map.cpp",
     '#include "occsweep/sweeps/replay.hpp"\n', "top", "tools/occsweep/cmd_map.cpp:1: map includes an engine header"),
    ("the library starts a shell", "sweeps/engine/src/progress.cpp",
     '\nstatic int shell = std::system("occsweep sweep");\n', "end", "sweeps/engine/src/progress.cpp:"),
]


def main() -> int:
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        tree = pathlib.Path(tmp)
        for name in CODE:
            src = ROOT / name
            if src.is_dir():
                shutil.copytree(src, tree / name, ignore=skip)
            elif src.is_file():
                shutil.copy(src, tree / name)
        shutil.copy(CHECK, tree / "tools" / "ci" / "check_layers.py")
        # The tree as it is passes: the planted violations below are then the only ones.
        code, out = check(tree)
        baseline = set(out.splitlines())
        if code != 0:
            failures.append(f"the unchanged tree: exit {code}\n{out}")
        for what, rel, text, where, expected in CASES:
            old = plant(tree, rel, text, where)
            try:
                code, out = check(tree)
                new = [line for line in out.splitlines() if line not in baseline]
                if code != 1 or not any(expected in line for line in new):
                    failures.append(f"{what}: exit {code}, no new line naming '{expected}':\n{out}")
                else:
                    print(f"ok: {what}: {next(line for line in new if expected in line)}")
            finally:
                restore(tree, rel, old)
    for f in failures:
        print("FAILED: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
