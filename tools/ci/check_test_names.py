#!/usr/bin/env python3
"""Test and section names that Catch2 2.13 can print when their test fails.

Catch2 2.13's console reporter prints a failing test's name, and each section's, as a header wrapped at 79 columns,
and indents the lines after the first by the position just after the name's first ": " (section names 2 more). When
that position leaves one column, a long name wraps into lines of one '-' each, forever: the failing test prints
nothing and hangs until ctest's timeout (1,200 s); with a few columns left it prints a column of word pieces. Names
keep at least 10 columns. Usage: check_test_names.py SOURCE_ROOT; exit 1 naming each
such name, 0 when there is none.
"""
import pathlib
import re
import sys

WIDTH = 79      # CATCH_CONFIG_CONSOLE_WIDTH (80) - 1
MIN_ROOM = 10   # columns a continuation line must keep

NAME = re.compile(r'\b(TEST_CASE|SECTION)\(\s*((?:"(?:[^"\\]|\\.)*"\s*)+)')
PIECE = re.compile(r'"((?:[^"\\]|\\.)*)"')


def unprintable(text):
    for match in NAME.finditer(text):
        name = "".join(PIECE.findall(match.group(2)))
        indent = 2 if match.group(1) == "SECTION" else 0
        colon = name.find(": ")
        if colon < 0 or indent + len(name) <= WIDTH:
            continue
        if WIDTH - (indent + colon + 2) < MIN_ROOM:
            yield text.count("\n", 0, match.start()) + 1, name


def main():
    root = pathlib.Path(sys.argv[1])
    found = [(path, line, name) for path in sorted((root / "tests").rglob("*.cpp"))
             for line, name in unprintable(path.read_text(encoding="utf-8"))]
    for path, line, name in found:
        print(f"{path.relative_to(root)}:{line}: Catch2 hangs printing this name when its test fails (its first "
              f"': ' leaves fewer than {MIN_ROOM} columns to the lines after the first): {name}")
    if found:
        return 1
    print("check_test_names: every test and section name prints")
    return 0


if __name__ == "__main__":
    sys.exit(main())
