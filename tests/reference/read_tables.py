#!/usr/bin/env python3
"""Reads data set names back from `occsweep compare`'s tables, each through a reader of its format, and prints one
line per name: "same" or what differs. The oracle of the table-escaping test (test_robust_outputs; docs/statistics.md,
"In occsweep compare").

Usage: read_tables.py FOLDER [--csv-only], where FOLDER holds names.json (a list of names) and, for name i, t-i.csv, t-i.md and
t-i.tex. CSV: Python's csv module must give the name exactly. Markdown: markdown-it-py (CommonMark with GitHub's
tables) must render the first body cell as the name's text, line breaks as spaces, in a row of the header's cells.
LaTeX: every table compiled with pdflatex (T1 fonts, booktabs); pdftotext must read the name between markers.
Markdown cells are compared without their edge spaces (CommonMark trims them); the PDF's text without spaces
(pdftotext guesses them from the gaps between glyphs), TeX's typographic single quotes counting as the ' and `
typed."""
import csv
import json
import os
import subprocess
import sys
import unicodedata
from html.parser import HTMLParser


class FirstTable(HTMLParser):
    """The cells' text of the first table, row by row: tags inside a cell (raw HTML that got through) add none."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.rows, self.cell, self.tables = [], None, 0

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables += 1
        elif self.tables == 1 and tag == "tr":
            self.rows.append([])
        elif self.tables == 1 and tag in ("td", "th"):
            self.cell = ""

    def handle_endtag(self, tag):
        if self.tables == 1 and tag in ("td", "th") and self.cell is not None:
            self.rows[-1].append(self.cell)
            self.cell = None

    def handle_data(self, data):
        if self.cell is not None:
            self.cell += data


def collapsed(text):
    """Without spaces (pdftotext guesses them from glyph gaps), ligature glyphs split (NFKC), and TeX's typographic
    single quotes as the keys typed."""
    text = unicodedata.normalize("NFKC", text).replace("\u2019", "'").replace("\u2018", "`")
    return "".join(text.split())


def csv_name(folder, i):
    with open(os.path.join(folder, f"t-{i}.csv"), newline="") as f:
        return next(csv.DictReader(f))["dataset"]


def markdown_problem(folder, i, name):
    from markdown_it import MarkdownIt  # only where it is installed (the test command installs it)

    with open(os.path.join(folder, f"t-{i}.md")) as f:
        html = MarkdownIt("commonmark").enable("table").render(f.read())
    table = FirstTable()
    table.feed(html)
    if len(table.rows) < 2 or len(table.rows[1]) != len(table.rows[0]):
        return "markdown: the first body row does not have the header's cells: %r" % table.rows[:2]
    cell, want = table.rows[1][0], name.replace("\n", " ").replace("\r", " ").strip()
    return None if cell == want else "markdown shows %r" % cell


def latex_texts(folder, count):
    """Each name's table compiled in one document; the text pdftotext reads between name i's markers."""
    with open(os.path.join(folder, "doc.tex"), "w") as doc:
        doc.write("\\documentclass{article}\n\\usepackage[T1]{fontenc}\n\\usepackage{booktabs}\n"
                  "\\usepackage{graphicx}\n\\usepackage{array}\n"
                  "\\usepackage[landscape,margin=1cm]{geometry}\n"
                  "\\makeatletter\\renewenvironment{table}{\\def\\@captype{table}\\par}{\\par}\\makeatother\n"
                  "\\begin{document}\n")
        for i in range(count):
            doc.write(f"BEGINNAME{i}\n\\input{{t-{i}.tex}}\nENDNAME{i}\n\\clearpage\n")
        doc.write("\\end{document}\n")
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "doc.tex"], cwd=folder,
                         capture_output=True, text=True, errors="replace")
    if run.returncode != 0:
        sys.exit("pdflatex failed:\n" + run.stdout[-3000:])
    text = subprocess.run(["pdftotext", "doc.pdf", "-"], cwd=folder, capture_output=True, text=True,
                          check=True).stdout
    return [text[text.index(f"BEGINNAME{i}") + len(f"BEGINNAME{i}"):text.index(f"ENDNAME{i}")] for i in range(count)]


def main():
    folder, csv_only = sys.argv[1], "--csv-only" in sys.argv[2:]
    with open(os.path.join(folder, "names.json")) as f:
        names = json.load(f)
    pdf = None if csv_only else latex_texts(folder, len(names))
    for i, name in enumerate(names):
        problems = []
        if csv_name(folder, i) != name:
            problems.append("csv gives %r" % csv_name(folder, i))
        problem = None if csv_only else markdown_problem(folder, i, name)
        if problem:
            problems.append(problem)
        if pdf is not None and collapsed(name) not in collapsed(pdf[i]):
            problems.append("the PDF shows %r" % " ".join(pdf[i].split())[:200])
        print("same" if not problems else "name %d %r: %s" % (i, name, "; ".join(problems)))


if __name__ == "__main__":
    main()
