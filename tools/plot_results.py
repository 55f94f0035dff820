#!/usr/bin/env python3
"""Figures of `occsweep plot` (docs/statistics.md, "Figures"): draws DATA.json, which the command computed from
results files, into FIG in DATA.json's "figure_format" (png, pdf or svg). Every number drawn comes from DATA.json.

usage: plot_results.py DATA.json FIG
"""
import json
import math
import re
import sys
import textwrap
import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

AUC = "AUC (area under the TPR-FDR curve, anchored)"


# The mark occsweep checks to know the script drew (PNG: its Software chunk; PDF and SVG: their Creator).
MARK = {"png": {"Software": "occsweep plot"}, "pdf": {"Creator": "occsweep plot"}, "svg": {"Creator": "occsweep plot"}}

class Style:
    """DATA.json's "style": the print width (None: each figure's screen size), the font size, and each method's
    display name, colour, marker and dash pattern, the same in every figure (occsweep computed them all)."""

    def __init__(self, d):
        s = d["style"]
        self.width, self.font_size, self.methods = s["width_in"], s["font_size"], s["methods"]
        self.small = max(6, self.font_size - 1)  # tick labels, legend entries and notes: never under 6 points
        plt.rcParams.update({"font.size": self.font_size, "axes.titlesize": self.font_size,
                             "legend.fontsize": self.small, "xtick.labelsize": self.small,
                             "ytick.labelsize": self.small, "svg.fonttype": "none", "pdf.fonttype": 42})

    def name(self, m):
        """A method's display name as text: a "$" is a dollar sign, not the start of matplotlib's mathtext."""
        return text(self.methods[m]["name"] if m in self.methods else m)

    def colour(self, m):
        return self.methods[m]["colour"]

    def marker(self, m):
        return self.methods[m]["marker"]

    def line(self, m):
        dash = self.methods[m]["dash"]
        return (0, tuple(dash)) if dash else "-"

    def size(self, screen_width, screen_height, rows=1):
        """The figure's size: the screen size, or the print width at the screen size's proportions, at least 2.4
        inches a row of panels (the axes, their labels and the legend's share of the height)."""
        if self.width is None:
            return screen_width, screen_height
        return self.width, max(self.width * screen_height / screen_width, 2.4 * rows)

    def panels(self, count, screen_columns=3):
        """Columns of small multiples: three on a screen or a page, fewer in a narrow column (1.7 in each at least)."""
        fit = screen_columns if self.width is None else max(1, int(self.width // 1.7))
        return max(1, min(screen_columns, fit, count))

    def title(self, setter, words):
        """A title on a screen; none in print, where the caption says it."""
        if self.width is None:
            setter(words)

    def label(self, words, inches):
        """An axis label in print, broken into lines that fit `inches` (about 0.55 em a character)."""
        if self.width is None:
            return words
        return textwrap.fill(words, max(12, int(inches * 72 / (0.55 * self.font_size))))


def text(words):
    """Words drawn as they are: matplotlib reads a pair of "$" as mathtext."""
    return words.replace("$", r"\$")


class DoesNotFit(Exception):
    pass


def save(fig, path, figure_format, style):
    # `path` is occsweep's temporary for the figure: occsweep renames it into place once this script succeeded. At a
    # print width the figure keeps that width (no crop: the layout already fits every label inside it), so its text
    # prints at the font size asked for.
    tight = "tight" if style.width is None else None
    fig.savefig(path, format=figure_format, dpi=150 if style.width is None else 300, bbox_inches=tight,
                metadata=MARK[figure_format])
    plt.close(fig)


def legend_below(fig, ax_or_axes, ncol):
    """The legend below the axes, off the data, in as many of `ncol` columns as fit the figure's width; the axes,
    their labels and any title are laid out above it (tight_layout within the rest of the figure)."""
    axes = ax_or_axes if isinstance(ax_or_axes, list) else [ax_or_axes]
    handles, labels = [], []
    for ax in axes:
        for h, l in zip(*ax.get_legend_handles_labels()):
            if l not in labels:
                handles.append(h)
                labels.append(l)
    renderer = fig.canvas.get_renderer()
    for n in range(max(1, min(ncol, len(labels))), 0, -1):
        legend = fig.legend(handles, labels, loc="lower center", ncol=n, bbox_to_anchor=(0.5, 0.0), frameon=False)
        if legend.get_window_extent(renderer).width <= fig.bbox.width:
            break
        legend.remove()
    else:
        raise DoesNotFit("a legend entry is wider than the figure")
    legend_in = legend.get_window_extent(renderer).height / fig.dpi + 0.05
    fig.tight_layout(rect=(0, min(0.6, legend_in / fig.get_figheight()), 1, 1), pad=0.3)


def curves(d, st):
    sets = d["sets"]
    cols = st.panels(len(sets))
    rows = math.ceil(len(sets) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=st.size(4.2 * cols, 3.6 * rows, rows), squeeze=False)
    panel_in = fig.get_figwidth() / cols
    methods = sorted({m["method"] for s in sets for m in s["methods"]})
    for ax, s in zip(axes.flat, sets):
        for m in s["methods"]:
            name = m["method"]
            xs, ys = zip(*m["points"]) if m["points"] else ([], [])
            # Each its own line style and marker, hollow markers and thin lines: a curve under another shows.
            ax.plot(xs, ys, linestyle=st.line(name), marker=st.marker(name), ms=4, mfc="none", lw=1.2,
                    color=st.colour(name), label=st.name(name))
            ax.annotate(f"{st.name(name)}: AUC {m['auc']:.4f}" if m["auc"] is not None else st.name(name),
                        xy=(0.98, 0.03 + 0.08 * s["methods"].index(m)), xycoords="axes fraction", ha="right",
                        fontsize=st.small, color=st.colour(name))
        ax.set_title(text(s["set"]), fontsize=st.small)
        ax.set_xlabel(st.label("FDR (false discovery rate)", panel_in))
        ax.set_ylabel(st.label("TPR (true positive rate)", fig.get_figheight() / rows * 0.8))
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(sets):]:
        ax.axis("off")
    shown = f"{len(sets)} of {d['sets_given']} sets" if d["sets_given"] > len(sets) else f"{len(sets)} sets"
    st.title(fig.suptitle, f"Best map of each method: TPR against FDR over p_t ({shown})")
    legend_below(fig, list(axes.flat), ncol=len(methods))
    return fig


def budget(d, st):
    fig, ax = plt.subplots(figsize=st.size(7, 4.5))
    for m in d["methods"]:
        name = m["method"]
        n = list(range(1, m["maps"] + 1))
        ax.plot(n, m["curve"], color=st.colour(name), linestyle=st.line(name), lw=1.4,
                label=f"{st.name(name)} ({m['maps']} maps)")
    if d["baseline_best"] is not None:
        ax.axhline(d["baseline_best"], color="k", ls="--", lw=1,
                   label=f"{st.name(d['baseline'])}: best of its whole grid")
    ax.set_xscale("log")
    ax.set_xlabel(st.label("maps tried at random from the method's grid (n, log scale)", fig.get_figwidth() * 0.8))
    ax.set_ylabel(st.label("expected best AUC, mean over sets", fig.get_figheight() * 0.45))
    st.title(ax.set_title, f"Budget curves over {d['sets']} set{'' if d['sets'] == 1 else 's'}: the expected best of n maps "
                              "(docs/statistics.md)")
    ax.grid(alpha=0.3, which="both")
    legend_below(fig, ax, ncol=3)
    return fig


def improvement(d, st):
    fig, (ax, right) = plt.subplots(1, 2, figsize=st.size(8.5, 4.5), sharey=True,
                                    gridspec_kw={"width_ratios": [4, 1.2]})
    for m in d["methods"]:
        name = m["method"]
        if m["points"]:
            ax.scatter([p[0] for p in m["points"]], [p[1] for p in m["points"]], s=22, color=st.colour(name),
                       marker=st.marker(name), edgecolors="k", linewidths=0.3, label=st.name(name), alpha=0.8)
    names = [st.name(m["method"]) for m in d["methods"]]
    for i, m in enumerate(d["methods"]):  # the mean's 95 % interval, one column per method
        iv = m["interval"]
        if iv is not None:
            right.errorbar([i], [iv["mean"]], yerr=[[iv["mean"] - iv["lower"]], [iv["upper"] - iv["mean"]]],
                           fmt=st.marker(m["method"]), color=st.colour(m["method"]), capsize=3, ms=5)
    for a in (ax, right):
        a.axhline(0, color="k", lw=0.8)
        a.grid(alpha=0.3)
    baseline = st.name(d["baseline"])
    ax.set_xlabel(st.label(f"best AUC of {baseline} on the set", fig.get_figwidth() * 0.6))
    ax.set_ylabel(st.label(f"improvement over {baseline} (%)", fig.get_figheight() * 0.45))
    st.title(ax.set_title, "Per set: the best of each method against the baseline's best")
    right.set_xticks(range(len(names)))
    right.set_xticklabels(names, rotation=45, ha="right", fontsize=st.small)
    right.set_xlim(-0.6, len(names) - 0.4)
    st.title(right.set_title, "mean, 95 % interval")
    legend_below(fig, ax, ncol=4)
    return fig


def params(d, st):
    ps = d["parameters"]
    if not ps:
        sys.exit("plot_results.py: no parameter of " + d["method"] + " takes more than one value in these files")
    cols = st.panels(len(ps))
    rows = math.ceil(len(ps) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=st.size(4.2 * cols, 3.4 * rows, rows), squeeze=False, sharey=True)
    for ax, p in zip(axes.flat, ps):
        # Black and grey, set apart by line and marker: no method's colour, which would read as that method.
        ax.plot(p["values"], p["mean"], "-o", ms=3, color="#000000", label="mean over the maps with this value")
        ax.plot(p["values"], p["best"], "--s", ms=3, color="#777777", label="best of the maps with this value")
        ax.set_xlabel(text(p["name"]))
        ax.grid(alpha=0.3)
    for ax in axes[:, 0]:
        ax.set_ylabel("AUC")
    for ax in list(axes.flat)[len(ps):]:
        ax.axis("off")
    st.title(fig.suptitle, f"{st.name(d['method'])}: AUC against each parameter, over every map and set given")
    legend_below(fig, list(axes.flat), ncol=2)
    return fig


FIGURES = {"curves": curves, "budget": budget, "improvement": improvement, "params": params}


def missing_glyph(d, warning):
    """What matplotlib's "Glyph N (...) missing from current font" warning means, and the fix: the character, the
    data set or method name that holds it, the font; None for another warning."""
    found = re.match(r"Glyph (\d+) ", str(warning))
    if not found:
        return None
    ch = chr(int(found.group(1)))
    names = [("data set", s["set"]) for s in d.get("sets", [])]
    names += [("method", m["name"]) for m in d["style"]["methods"].values()]
    held = next((f" of the {what} name {name!r}" for what, name in names if ch in name), "")
    return (f"the font ({plt.rcParams['font.sans-serif'][0]}) has no glyph for the character {ch!r} (U+{ord(ch):04X}){held}: import the data set "
            "again under a name without it (occsweep import --name), give the method a display name without it "
            "(--style), or name a font that has it first in font.sans-serif of a matplotlibrc")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    try:
        with open(sys.argv[1]) as f:
            d = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"plot_results.py: {sys.argv[1]}: {e}")
    if d.get("kind") not in FIGURES:
        sys.exit(f"plot_results.py: {sys.argv[1]}: unknown kind {d.get('kind')!r}")
    figure_format = d.get("figure_format", "png")
    if figure_format not in MARK:
        sys.exit(f"plot_results.py: {sys.argv[1]}: unknown figure_format {figure_format!r}")
    # What would leave a figure unfit for print is an error, not a warning on stderr: text that does not fit, a
    # character the font cannot draw.
    warnings.filterwarnings("error", message="Tight layout not applied")
    warnings.filterwarnings("error", message="Glyph .* missing from")
    try:
        style = Style(d)
        save(FIGURES[d["kind"]](d, style), sys.argv[2], figure_format, style)
    except (DoesNotFit, UserWarning) as e:
        glyph = missing_glyph(d, e)
        if glyph:
            sys.exit(f"plot_results.py: cannot draw the {d['kind']} figure: {glyph}")
        sys.exit(f"plot_results.py: the {d['kind']} figure's text does not fit: {e}; choose a wider --print-width, a "
                 "smaller --font-size or shorter display names (--style)")
    except Exception as e:  # one line, never a traceback: occsweep reports the failure and writes nothing
        first = str(e).splitlines()[0] if str(e) else ""
        sys.exit(f"plot_results.py: cannot draw the {d['kind']} figure: {type(e).__name__}: {first}")


if __name__ == "__main__":
    main()
