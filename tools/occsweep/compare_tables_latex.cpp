// compare --latex (compare_tables.hpp): the per-set table and the statistics as booktabs tables for a plain article,
// names shown character for character, and the names pdflatex cannot typeset refused before anything is written.
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "compare_cells.hpp"
#include "method_style.hpp"
#include "occsweep/io/control_characters.hpp"

namespace occsweep::cli {
namespace {

// Text as LaTeX text mode shows it, character for character under T1 fonts (names come from users' files): the ten
// specials escaped; '<', '>', '|' (other glyphs under OT1) by their text commands; a pair that would form a
// ligature (--, ,,, '', ``, !`, ?`) broken by "{}"; line breaks as spaces. Quotes stay typographic (' shows as a
// closing quote). docs/statistics.md, "In occsweep compare".
std::string latexEscaped(const std::string& s) {
  static constexpr std::string_view kLigaturePairs[] = {"--", ",,", "''", "``", "!`", "?`"};
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char ch = s[i];
    switch (ch) {
      case '_': case '%': case '&': case '#': case '$': case '{': case '}': out += '\\', out += ch; break;
      case '\\': out += "\\textbackslash{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '~': out += "\\textasciitilde{}"; break;
      case '<': out += "\\textless{}"; break;
      case '>': out += "\\textgreater{}"; break;
      case '|': out += "\\textbar{}"; break;
      case '\n': case '\r': out += ' '; break;
      default: out += ch;
    }
    for (std::string_view pair : kLigaturePairs)
      if (i + 1 < s.size() && ch == pair[0] && s[i + 1] == pair[1]) out += "{}";
  }
  return out;
}

// Whether pdflatex typesets `c` in the set-up the tables are for (T1 fonts, LaTeX's UTF-8 input): printable ASCII,
// line breaks and tabs (spaces in the table), and the Latin letters and signs of U+00A0-U+017E but the eight T1 has
// no glyph for (tried one by one with pdflatex).
bool latexTypesets(char32_t c) {
  static constexpr char32_t kNotInT1[] = {0x126, 0x127, 0x138, 0x13F, 0x140, 0x149, 0x166, 0x167};
  if (c == '\n' || c == '\r' || c == '\t' || (c >= 0x20 && c <= 0x7E)) return true;
  return c >= 0xA0 && c <= 0x17E && std::find(std::begin(kNotInT1), std::end(kNotInT1), c) == std::end(kNotInT1);
}

// A float taller than the page is lost off its end: the per-set table holds at most this many sets per float (a
// plain article's page holds about 52 in \small), and continues in the next.
constexpr std::size_t kSetsPerLatexTable = 40;

// The per-set table within the text width, for a plain article with booktabs and graphicx: each method's name spans
// its columns (its AUC, and but for the baseline its improvement in percent) over a short second header line, so a
// column is as wide as its numbers; names left, numbers right (one number of decimals per column, so the points
// align). Shrunk to the text width only when still wider (\resizebox of the natural width or \linewidth, whichever is
// less); over kSetsPerLatexTable sets, in several floats. `c` is perSetCells': its header line is replaced by the
// two built here.
std::string latexPerSet(const Cells& c, const ComparisonTables& t, const std::string& caption) {
  std::string names = " & ", rules, units = "data set & pcs";
  std::size_t column = 3;  // LaTeX counts columns from 1: the methods' start after data set and pcs
  for (const std::string& m : t.methods) {
    const std::size_t span = m == t.baseline ? 1 : 2;
    names += " & \\multicolumn{" + std::to_string(span) + "}{c}{" + latexEscaped(displayNameOf(m)) + "}";
    rules += "\\cmidrule(lr){" + std::to_string(column) + "-" + std::to_string(column + span - 1) + "}";
    units += span == 1 ? " & AUC" : " & AUC & \\%";
    column += span;
  }
  const std::size_t sets = c.size() - 1;
  std::ostringstream o;
  for (std::size_t first = 1; first == 1 || first <= sets; first += kSetsPerLatexTable) {
    const std::size_t last = std::min(sets, first + kSetsPerLatexTable - 1);
    const std::string part = sets > kSetsPerLatexTable ? " (sets " + std::to_string(first) + "-" +
                                                             std::to_string(last) + " of " + std::to_string(sets) + ")"
                                                       : "";
    o << "\\begin{table}\n\\centering\n\\caption{" << latexEscaped(caption + part) << "}\n\\small\n"
      << "\\setlength{\\tabcolsep}{4pt}\n\\resizebox{\\ifdim\\width>\\linewidth\\linewidth\\else\\width\\fi}{!}{%\n"
      << "\\begin{tabular}{ll" << std::string(c[0].size() - 2, 'r') << "}\n\\toprule\n";
    o << names << " \\\\\n" << rules << "\n" << units << " \\\\\n\\midrule\n";
    for (std::size_t r = first; r <= last; ++r) {
      for (std::size_t i = 0; i < c[r].size(); ++i) o << (i ? " & " : "") << latexEscaped(c[r][i]);
      o << " \\\\\n";
    }
    o << "\\bottomrule\n\\end{tabular}}\n\\end{table}\n";
  }
  return o.str();
}

// The statistics turned on their side, a row per statistic and a column per method, each column a paragraph of its
// share of the text width (array's p columns, ragged right): however many statistics, it fits the page, and long
// verdicts wrap within their column.
std::string latexStatistics(const Cells& c, const std::string& caption) {
  const std::size_t methods = c.size() - 1;
  std::ostringstream o;
  // Four methods or more: a smaller size, so that the verdicts wrapped in narrower columns stay within the page.
  o << "\\begin{table}\n\\centering\n\\caption{" << latexEscaped(caption) << "}\n"
    << (methods >= 4 ? "\\footnotesize\n" : "\\small\n") << "\\begin{tabular}{>{\\raggedright\\arraybackslash}p{\\dimexpr 0.28\\linewidth-2\\tabcolsep\\relax}*{"
    << methods << "}{>{\\raggedright\\arraybackslash}p{\\dimexpr 0.72\\linewidth/" << methods
    << "-2\\tabcolsep\\relax}}}\n\\toprule\n";
  for (std::size_t i = 0; i < c[0].size(); ++i) {
    o << (i == 0 ? "" : latexEscaped(c[0][i]));
    for (std::size_t r = 1; r < c.size(); ++r) o << " & " << latexEscaped(c[r][i]);
    o << " \\\\\n" << (i == 0 ? "\\midrule\n" : "");
  }
  o << "\\bottomrule\n\\end{tabular}\n\\end{table}\n";
  return o.str();
}

// Lines under the tables as a list, each item the text itself.
std::string latexItems(const std::vector<std::string>& lines) {
  if (lines.empty()) return "";
  std::string out = "\\begin{itemize}\n";
  for (const std::string& line : lines) out += "  \\item " + latexEscaped(line) + "\n";
  return out + "\\end{itemize}\n";
}

}  // namespace

void requireLatexCharacters(const std::vector<ResultsFile>& files, const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < files.size(); ++i)
    for (const Utf8Character& c : utf8Characters(files[i].header.dataset_name)) {
      if (latexTypesets(c.code_point)) continue;
      char code[16];
      std::snprintf(code, sizeof code, "U+%04X", static_cast<unsigned>(c.code_point));
      throw std::invalid_argument(
          "--latex: " + names[i] + ": the data set name '" + files[i].header.dataset_name + "' holds '" +
          std::string(c.bytes) + "' (" + (c.code_point == kNotUtf8 ? std::string("a byte that is not UTF-8") : code) +
          "), which pdflatex cannot typeset in the T1 fonts the table is for (printable ASCII and the Latin letters "
          "of U+00A0-U+017E; docs/statistics.md): write --markdown or --csv, which hold any character, or import the "
          "data set again under a name pdflatex can typeset (import --name) and sweep that");
    }
}

std::string latexTables(const ComparisonTables& t) {
  // The truth in the caption, which goes wherever the float goes; the warnings after the float, as many as there
  // are: a float cannot grow past the page.
  const std::vector<std::string> notes = truthNotes(t);
  const std::size_t warnings = notes.size() - 1;
  const std::string listed = warnings ? "; " + std::to_string(warnings) + (warnings == 1 ? " warning" : " warnings") +
                                            " of truth coverage or alignment listed after the table"
                                      : "";
  std::string out = "% occsweep compare --latex: needs \\usepackage{booktabs}, \\usepackage{graphicx} and "
                    "\\usepackage{array}; with \\usepackage[T1]{fontenc} every character of a name shows as typed\n" +
                    latexPerSet(perSetCells(t), t,
                                mixedNote(t) + "Best AUC per set, and (%) the improvement over " +
                                    displayNameOf(t.baseline) + " in percent; " + notes.front() + listed) +
                    latexItems({notes.begin() + 1, notes.end()});
  if (t.statistics.empty()) return out;
  const stats::VerdictRules& rules = t.rules;
  out += latexStatistics(withDisplayNames(statisticsCells(t.statistics, t.baseline), t.methods, 0),
               mixedNote(t) + "Statistics against " + displayNameOf(t.baseline) + ", the " +
               (t.statistics.front().optima.unit_name == "scenes" ? "scene" : "data set") + " as the unit. Verdicts: gain or "
               "loss only when the 95% BCa interval excludes 0 and the exact test (Wilcoxon signed-rank, or the sign "
               "test on ties) rejects at alpha " + cell(rules.alpha, "%g") + " after Holm's correction over the "
               "methods compared, leaning the interval's way; negligible when the sign test puts the median, and the "
               "interval the mean, within +-" + cell(rules.smallest_effect, "%g") + " %");
  // Each verdict's basis (its sample, test and correction) under the tables, as compare prints it.
  std::vector<std::string> bases = verdictBases(t.statistics);
  for (std::string& line : bases) line = withDisplayNames(line, t.methods);  // as the tables above name the methods
  return out + latexItems(bases);
}

}  // namespace occsweep::cli
