#!/usr/bin/env python3
"""Checks the layer rules of docs/architecture.md on a source tree; CI runs it (tests/CMakeLists.txt too).

  1. Every quoted #include resolves to a file of a known part, and points down: a part includes only itself and
     the parts below it (ALLOWED). Test groups follow the layer they test. Core (the contract) includes no method.
  2. Every library part's CMakeLists.txt lists each of its sources (no glob) and links only parts it may include.
  3. The library (io, core, methods, eval, stats, sweeps/*) starts no shell and knows no source tree: no std::system, popen or
     OCCSWEEP_SOURCE_DIR in it.

Usage: check_layers.py ROOT. Prints one line per violation (file:line: what, and the rule) and exits 1, or a
summary and exits 0.
"""
import pathlib
import re
import sys

LIBRARY = ["io", "core", "methods", "eval", "stats", "grid", "results", "engine", "cluster", "reproduce"]
# What each part may include (itself implied). Order of the layers: io, core <- methods, eval, stats <- sweeps <- tools.
# io (file safety) includes nothing of occsweep: it knows no data set, result or method. Core is the contract every
# method implements and knows none (methods/ has them); the engines use the contract only, and the parts that build
# or register the shipped methods (reproduce, the command, bench, examples, tests) may include methods.
ALLOWED = {
    "io": [],
    "core": [],
    "methods": ["core"],
    "eval": ["io", "core"],
    "stats": ["core"],
    "grid": ["io", "core", "eval"],
    "results": ["io", "core", "eval", "stats", "grid"],
    "engine": ["io", "core", "eval", "grid", "results"],
    "cluster": ["io", "core", "eval", "grid", "results", "engine"],
    "reproduce": ["io", "core", "methods", "eval", "stats", "grid", "results", "engine"],
    "data": ["io", "core", "eval"],
    "stereo": ["io", "core", "eval", "data"],
    "cli": LIBRARY + ["data", "stereo"],
    "bench": LIBRARY + ["data", "stereo", "tests"],  # the tests' helpers: where the built command is
    "examples": LIBRARY,
    "tests": ["core", "methods"],  # helpers shared by the test groups; the main registers the methods
    "tests/core": ["core", "tests"],
    "tests/methods": ["core", "methods", "tests"],
    "tests/eval": ["io", "core", "methods", "eval", "stats", "tests"],
    "tests/sweeps": LIBRARY + ["tests"],
    "tests/tools": LIBRARY + ["data", "stereo", "tests"],
    "tests/fuzz": LIBRARY + ["data", "tests"],
}
# Generated at build time (sweeps/engine/version.hpp.in).
GENERATED = {"occsweep/sweeps/version.hpp": "engine"}
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')


def part_of(rel: pathlib.PurePosixPath) -> str | None:
    p = rel.parts
    if p[0] in ("io", "core", "methods"):
        return p[0]
    if p[0] == "eval":
        return "stats" if "stats" in p[1:] else "eval"
    if p[0] == "sweeps" and len(p) > 2 and p[1] in LIBRARY:
        return p[1]
    if p[0] == "tools" and len(p) > 2 and p[1] in ("data", "stereo"):
        return p[1]
    if p[0] == "tools" and len(p) > 2 and p[1] == "occsweep":
        return "cli"
    if p[0] in ("bench", "examples"):
        return p[0]
    if p[0] == "tests":
        if len(p) > 2 and p[1] in ("core", "methods", "eval", "sweeps", "tools", "fuzz"):
            return "tests/" + p[1]
        return "tests"
    return None


def include_roots(root: pathlib.Path) -> list[pathlib.Path]:
    return sorted(root.glob("io/include")) + sorted(root.glob("core/include")) + sorted(root.glob("methods/include")) + \
        sorted(root.glob("methods/*/include")) + sorted(root.glob("eval/include")) + \
        sorted(root.glob("sweeps/*/include")) + sorted(root.glob("tools/*/include")) + [root / "tests"]


def resolve(root, roots, source: pathlib.Path, name: str):
    """The file an #include "name" in `source` means, as the compiler finds it: beside the source first."""
    for base in [source.parent] + roots:
        candidate = base / name
        if candidate.is_file():
            return candidate.resolve().relative_to(root)
    return None


def check_includes(root, files, errors):
    roots = include_roots(root)
    count = 0
    for source in files:
        rel = pathlib.PurePosixPath(source.relative_to(root).as_posix())
        part = part_of(rel)
        if part is None:
            continue
        for number, line in enumerate(source.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            count += 1
            name = m.group(1)
            target = GENERATED.get(name)
            if target is None:
                found = resolve(root, roots, source, name)
                if found is None:
                    if name.startswith("occsweep/"):
                        errors.append(f"{rel}:{number}: #include \"{name}\" is no header of the tree")
                    continue
                target = part_of(pathlib.PurePosixPath(found.as_posix()))
            if target is None or target == part:
                continue
            if target not in ALLOWED[part]:
                allowed = ", ".join(ALLOWED[part]) or "nothing else"
                errors.append(f"{rel}:{number}: {part} includes \"{name}\" ({target}): an upward or sideways "
                              f"arrow; {part} may include only {allowed} (docs/architecture.md)")
    return count


def check_cmake(root, errors):
    parts = [("io", root / "io"), ("core", root / "core"), ("methods", root / "methods"), ("eval", root / "eval")] + \
        [(p, root / "sweeps" / p) for p in LIBRARY if (root / "sweeps" / p).is_dir()]
    for part, folder in parts:
        cmake = folder / "CMakeLists.txt"
        if not cmake.is_file():
            errors.append(f"{folder.relative_to(root)}: no CMakeLists.txt of its own (every part is its own target)")
            continue
        text = cmake.read_text()
        rel = cmake.relative_to(root)
        if re.search(r"file\s*\(\s*GLOB", text):
            errors.append(f"{rel}: globs its sources; a part lists them")
        for source in sorted(s for s in folder.rglob("*.cpp") if "src" in s.relative_to(folder).parts):  # methods/*/src
            if source.relative_to(folder).as_posix() not in text:
                errors.append(f"{rel}: does not list {source.relative_to(root)}")
        owner = part
        for number, line in enumerate(text.splitlines(), 1):
            declared = re.match(r"\s*occsweep_library\(\s*(\w+)", line)
            if declared:  # eval/CMakeLists.txt declares two parts, eval and stats
                owner = declared.group(1)
            for linked in re.findall(r"occsweep::(\w+)", line.split("#")[0]):
                if linked != owner and linked not in ALLOWED.get(owner, []):
                    errors.append(f"{rel}:{number}: {owner} links occsweep::{linked}; {owner} may use only "
                                  f"{', '.join(ALLOWED.get(owner, [])) or 'nothing else'}")


def check_command_sources(root, errors):
    """The command line is an object library of listed files (tools/CMakeLists.txt): a subcommand file left out
    would never register, and no test would name it. And `map` builds any method without the engine (it runs
    MappingMethod::buildMap with its own executor: docs/architecture.md, "Threads")."""
    cmake = root / "tools" / "CMakeLists.txt"
    text = cmake.read_text() if cmake.is_file() else ""
    for source in sorted((root / "tools" / "occsweep").glob("*.cpp")):
        if source.name != "main.cpp" and f"occsweep/{source.name}" not in text:
            errors.append(f"tools/CMakeLists.txt: does not list {source.relative_to(root)} in occsweep_cli")
    cmd_map = root / "tools" / "occsweep" / "cmd_map.cpp"
    if cmd_map.is_file():
        for number, line in enumerate(cmd_map.read_text().splitlines(), 1):
            if re.match(r'\s*#\s*include\s*"occsweep/sweeps/(replay|sweep|sweep_engine|progress)\.hpp"', line):
                errors.append(f"tools/occsweep/cmd_map.cpp:{number}: map includes an engine header")


def check_library_runs_nothing(root, files, errors):
    banned = re.compile(r"\bstd::system\s*\(|\bpopen\s*\(|OCCSWEEP_SOURCE_DIR")
    for source in files:
        rel = pathlib.PurePosixPath(source.relative_to(root).as_posix())
        if part_of(rel) not in LIBRARY and not (rel.parts[0] == "sweeps" and rel.name == "CMakeLists.txt"):
            continue
        for number, line in enumerate(source.read_text(errors="replace").splitlines(), 1):
            if banned.search(line.split("//")[0]):
                errors.append(f"{rel}:{number}: the library starts a shell or knows the source tree "
                              f"(std::system, popen, OCCSWEEP_SOURCE_DIR); the command hands such things in")


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    root = pathlib.Path(sys.argv[1]).resolve()
    files = [f for f in sorted(root.rglob("*")) if f.suffix in (".hpp", ".cpp", ".h", ".txt")
             and f.is_file() and not {"build", ".git"} & set(f.relative_to(root).parts)
             and (f.suffix != ".txt" or f.name == "CMakeLists.txt")]
    errors = []
    count = check_includes(root, [f for f in files if f.suffix != ".txt"], errors)
    check_cmake(root, errors)
    check_command_sources(root, errors)
    check_library_runs_nothing(root, files, errors)
    for e in errors:
        print(e)
    if errors:
        print(f"check_layers: {len(errors)} violation(s) of docs/architecture.md")
        return 1
    print(f"check_layers: {count} includes in {len(files)} files, every arrow points down")
    return 0


if __name__ == "__main__":
    sys.exit(main())
