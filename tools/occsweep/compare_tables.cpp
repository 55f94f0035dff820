// The tables of `occsweep compare` (compare_tables.hpp): every format is made from the same cells.
#include "compare_tables.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string_view>

#include "method_style.hpp"
#include "occsweep/io/control_characters.hpp"
#include "occsweep/sweeps/csv_text.hpp"
#include "occsweep/sweeps/results_verify.hpp"

namespace occsweep::cli {
namespace {

using Cells = std::vector<std::vector<std::string>>;  // a header line, then the body

// A number occsweep prints is either right or not printed (docs/robustness.md): "-" where there is none.
std::string cell(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string intervalText(const std::optional<stats::BootstrapInterval>& interval) {
  if (!interval) return "-";
  const auto& i = *interval;
  return cell(i.estimate, "%+.2f") + " [" + cell(i.lower, "%+.2f") + ", " + cell(i.upper, "%+.2f") + "]";
}

std::string crossValidatedText(const CrossValidated& c) {
  return c.groups ? cell(c.score, "%.4f") + " (gap " + cell(c.gap, "%.4f") + ")" : "-";
}

std::string budgetText(const BudgetSummary& b) {
  if (!b.maps) return "-";
  return cell(b.expected_best_at_budget, "%.4f") + " at " + std::to_string(b.budget) + " maps; " +
         (b.first_above_baseline ? "passes at " + std::to_string(*b.first_above_baseline) + " of "
                                 : std::string("does not pass within ")) +
         std::to_string(b.maps);
}

std::string testText(const DatasetComparison& c) {
  if (!c.test) return "-";
  return cell(c.test->p_value, "%.3g") + " (Holm " + cell(c.holm_p, "%.3g") + ")";
}

// "60 (20)": sets and data sets; "60 (20 over 10 scenes)" where provenance grouped the data sets into scenes.
std::string sampleCell(const MethodStatistics& s) {
  const bool scenes = s.optima.unit_name != "data sets";
  return std::to_string(s.sets) + " (" + std::to_string(s.datasets) +
         (scenes ? " over " + std::to_string(s.scenes) + (s.scenes == 1 ? " scene" : " " + s.optima.unit_name) : "") +
         ")";
}

// The verdicts over their unit, the scene or the data set (docs/statistics.md, "Verdicts"): every header that counts
// or holds out units names it; the per-set interval stays as description.
Cells statisticsCells(const std::vector<MethodStatistics>& statistics, const std::string& baseline) {
  const std::string units = statistics.front().optima.unit_name, unit = units.substr(0, units.size() - 1);
  std::string hyphenated = unit;
  std::replace(hyphenated.begin(), hyphenated.end(), ' ', '-');
  Cells c{{"method", units == "data sets" ? "sets (data sets)" : "sets (data sets over " + units + ")",
           "better/worse/tie", "holds " + baseline + "'s best", "improvement % over sets [95% CI]", "over " + units,
           "exact test over " + units + ": p (Holm)", "per-set optimum", "leave-one-set-out (gap)",
           "leave-one-" + hyphenated + "-out (gap)", "cross-validated improvement % (by " + unit + ")",
           "leave-one-set-out improvement % (optimistic)", "budget: expected best (vs " + baseline + "'s best)",
           "verdict (optima)", "verdict (cross-validated)"}};
  for (const MethodStatistics& s : statistics) {
    const bool base = s.is_baseline;
    c.push_back({s.method, sampleCell(s),
                 base ? "-" : std::to_string(s.better) + "/" + std::to_string(s.worse) + "/" + std::to_string(s.ties),
                 base ? "-" : std::to_string(s.sets_holding_baseline_best) + " of " + std::to_string(s.sets),
                 intervalText(s.improvement_percent), intervalText(s.optima.interval), base ? "-" : testText(s.optima),
                 cell(s.mean_best_auc, "%.4f"), crossValidatedText(s.leave_one_set_out),
                 crossValidatedText(s.leave_one_dataset_out), intervalText(s.cross_validated.interval),
                 intervalText(s.leave_one_set_out_improvement), base ? "-" : budgetText(s.budget),
                 base ? "baseline" : s.optima.verdict.text, base ? "baseline" : s.cross_validated.verdict.text});
  }
  return c;
}

// Where the method's results hold a map scoring the baseline's best AUC exactly (found from the maps, not the
// names), its optimum there is at least the baseline's: a tie at the optimum is no evidence, and where that holds on
// every set the optima verdict cannot be a loss; the cross-validated verdict can.
std::string nestingText(const MethodStatistics& s) {
  auto of = [&](std::size_t n) { return std::to_string(n) + " of " + std::to_string(s.sets); };
  std::string text = s.method + ": on " + of(s.sets_holding_baseline_best) + " sets its results hold a map "
                     "scoring the baseline's best AUC exactly, so its optimum there is at least the baseline's; "
                     "better on " + of(s.better) + ", equal on " + of(s.ties) + ", worse on " + of(s.worse);
  if (s.sets_holding_baseline_best == s.sets)
    text += " (on every set: the optima verdict cannot be a loss; the cross-validated one can)";
  return text;
}

// Each verdict with its sample, test and correction, one line each, and last which verdicts Holm's correction
// ran over together (docs/statistics.md, "Verdicts").
std::vector<std::string> verdictBases(const std::vector<MethodStatistics>& statistics) {
  std::vector<std::string> lines;
  std::string families;
  for (const MethodStatistics& s : statistics) {
    if (s.is_baseline) continue;
    for (const auto& [what, c] : {std::pair<const char*, const DatasetComparison&>{"optima", s.optima},
                                  {s.cross_validated.unit_name == "scenes" ? "cross-validated by scene"
                                                                           : "cross-validated by data set",
                                   s.cross_validated}})
      lines.push_back(s.method + ", " + what + ": " + c.verdict.text +
                      (c.verdict.basis.empty() ? "" : ": " + c.verdict.basis));
    if (s.sets_holding_baseline_best) lines.push_back(nestingText(s));
    if (families.empty())
      families = "Holm families, each corrected by itself: " + s.optima.holm_family + "; " +
                 s.cross_validated.holm_family;
  }
  if (!families.empty()) lines.push_back(families);
  return lines;
}

// Per set: the data set, its point cloud set, each method's AUC and (but the baseline) its improvement.
Cells perSetCells(const ComparisonTables& t) {
  Cells c{{"data set", "pcs"}};
  for (const std::string& m : t.methods) {
    c[0].push_back(m + " AUC");
    if (m != t.baseline) c[0].push_back(m + " vs " + t.baseline + " %");
  }
  for (const ComparisonRow& row : t.rows) {
    std::vector<std::string> line{row.dataset, row.point_cloud_set};
    for (const std::string& m : t.methods) {
      const auto best = row.best(m);
      line.push_back(best ? cell(best->auc, "%.4f") : "-");
      if (m != t.baseline) line.push_back(cell(row.improvementPercent(m, t.baseline), "%+.2f"));
    }
    c.push_back(std::move(line));
  }
  return c;
}

// A Markdown table cell that CommonMark with GitHub's tables shows as the text itself (names come from users' files):
// the characters that open something inside a cell backslash-escaped ('|' ends the cell; '*', '_', '~', '`', '<',
// '&', '[', ']' start emphasis, strikethrough, code, HTML, entities and links; '\\' escapes), a line break as a space
// (it would end the row). docs/statistics.md, "In occsweep compare".
std::string markdownCell(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (std::string_view("|*_~`<>&[]\\").find(ch) != std::string_view::npos) out += '\\';
    out += (ch == '\n' || ch == '\r') ? ' ' : ch;
  }
  return out;
}

// Columns from `first_number_column` on hold numbers: right-aligned, so that their decimal points line up.
std::string markdown(const Cells& c, std::size_t first_number_column) {
  std::ostringstream o;
  for (std::size_t r = 0; r < c.size(); ++r) {
    o << "|";
    for (const auto& v : c[r]) o << ' ' << markdownCell(v) << " |";
    o << '\n';
    if (r == 0) {
      o << "|";
      for (std::size_t i = 0; i < c[0].size(); ++i) o << (i < first_number_column ? "---|" : "---:|");
      o << '\n';
    }
  }
  return o.str();
}

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

// `c` with every method name in it (a row's first cell, a word of a header: "knn AUC", "holds octomap's best")
// shown by its display name. Data set names, which a user chooses, are cells of their own and stay as they are.
Cells withDisplayNames(Cells c, const std::vector<std::string>& methods, std::size_t name_columns) {
  for (std::size_t r = 0; r < c.size(); ++r)
    for (std::size_t i = r == 0 ? 0 : name_columns; i < c[r].size(); ++i) {
      std::istringstream words(c[r][i]);
      std::string shown, word;
      while (words >> word) {
        const std::size_t end = word.find_last_not_of(",;:") + 1;  // punctuation after a name stays after it
        const std::string bare = word.substr(0, end), after = word.substr(end);
        for (const std::string& m : methods)
          if (bare == m || bare == m + "'s") word = displayNameOf(m) + bare.substr(m.size()) + after;
        shown += (shown.empty() ? "" : " ") + word;
      }
      if (!shown.empty()) c[r][i] = shown;
    }
  return c;
}

// One line of text (a verdict's basis) with the methods by their display names, as the tables show them.
std::string withDisplayNames(const std::string& line, const std::vector<std::string>& methods) {
  return withDisplayNames(Cells{{line}}, methods, 0)[0][0];
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

}  // namespace

std::vector<ResultsFile> readChecked(const std::vector<std::string>& files, MapDetail detail) {
  std::vector<ResultsFile> in;
  // What `results check` refuses is never read, and what is read is what was checked: one open of each file
  // (docs/results-format.md, "Reading").
  for (const auto& f : files) in.push_back(readCheckedResults(f, detail));
  return in;
}

// Within 100 columns: a block per method, one labelled line per statistic (the wide table is --csv's, --markdown's
// and --latex's), then each verdict's basis; a value too long for its line goes on under its label's end.
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

std::string statisticsText(const ComparisonTables& t) {
  if (t.statistics.empty()) return "";
  const Cells c = statisticsCells(t.statistics, t.baseline);
  std::size_t label = 0;
  for (std::size_t i = 1; i < c[0].size(); ++i) label = std::max(label, c[0][i].size());
  std::ostringstream o;
  o << "statistics against " << t.baseline << " over the sets where both have an AUC (docs/statistics.md):\n";
  for (std::size_t r = 1; r < c.size(); ++r) {
    o << c[r][0] << '\n';
    for (std::size_t i = 1; i < c[r].size(); ++i) {
      if (c[r][i].empty() || c[r][i] == "-") continue;
      const std::string lines = wrappedLines(c[r][i], 2 + label + 2, kTerminalColumns);
      if (lines.empty()) continue;  // blanks only
      o << "  " << c[0][i] << std::string(label - c[0][i].size() + 2, ' ') << lines.substr(2 + label + 2);
    }
  }
  const std::vector<std::string> bases = verdictBases(t.statistics);
  if (!bases.empty())
    o << "verdicts over " << t.statistics.front().optima.unit_name
      << " (exact test after Holm's correction, interval, smallest effect):\n";
  for (const std::string& line : bases) {
    const std::string lines = wrappedLines(line, 4, kTerminalColumns);
    if (!lines.empty()) o << "  " << lines.substr(4);  // the first line 2 in, the rest 4
  }
  return o.str();
}

std::string bestParametersText(const BestMap& best, const std::vector<ResultsFile>& files) {
  const ParameterLayout& layout = files[best.file].header.parameters;
  std::string text;
  // Every digit (the shortest text that reads back to the value): what `map --NAME` is given reproduces the map.
  for (std::size_t i = 0; i < layout.names.size(); ++i)
    text += (text.empty() ? "" : " ") + layout.names[i] + "=" + csvNumber(toDouble(best.params.values[i]));
  return text;
}

std::string wrappedLines(const std::string& text, std::size_t indent, std::size_t width) {
  std::istringstream words(text);
  std::string out, line, word;
  const std::size_t room = width > indent + 1 ? width - indent : 1;
  while (words >> word) {
    if (!line.empty() && indent + line.size() + 1 + word.size() > width) out += std::string(indent, ' ') + line + '\n', line.clear();
    // A word longer than a line (a long path) goes on over several, cut where the line ends.
    for (; line.empty() && word.size() > room; word.erase(0, room))
      out += std::string(indent, ' ') + word.substr(0, room) + '\n';
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) out += std::string(indent, ' ') + line + '\n';
  return out;
}

std::string cutLines(const std::string& text, std::size_t indent, std::size_t width) {
  const std::size_t room = width > indent + 4 ? width - indent : 4;  // a UTF-8 character is at most 4 bytes
  std::string out;
  for (std::size_t at = 0; at < text.size();) {
    std::size_t end = std::min(text.size(), at + room);
    while (end < text.size() && end > at && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
    out += std::string(indent, ' ') + text.substr(at, end - at) + '\n';
    at = end;
  }
  return out;
}

nlohmann::json parameterFields(const BestMap& best, const std::vector<ResultsFile>& files) {
  return toJson(best.params, files[best.file].header.parameters);
}

// Said before every table of a comparison made with --allow-mixed: its numbers do not compare like with like.
std::string mixedNote(const ComparisonTables& t) {
  if (t.mixed.empty()) return "";
  return "Mixed settings (compare --allow-mixed): the files differ in " + std::to_string(t.mixed.size()) +
         (t.mixed.size() == 1 ? " way" : " ways") + " (the comparison's JSON lists them, under mixed), so these numbers "
         "do not compare like with like. ";
}

std::string csvTable(const ComparisonTables& t) {
  // Columns: every method's, and every parameter any of its best maps has.
  std::vector<std::string> header{"dataset", "point_cloud_set", "dataset_hash"};
  if (!t.mixed.empty()) header.push_back("mixed_settings");  // every row: compared with --allow-mixed
  header.push_back("unit");
  std::vector<std::pair<std::string, std::vector<std::string>>> columns;  // method, its parameters
  for (const std::string& m : t.methods) {
    std::vector<std::string> params;
    for (const ComparisonRow& row : t.rows)
      if (const auto best = row.best(m)) {
        for (const auto& name : t.files[best->file].header.parameters.names) params.push_back(name);
        break;
      }
    header.insert(header.end(), {m + ".auc", m + ".improvement_percent", m + ".file"});
    for (const auto& p : params) header.push_back(m + "." + p);
    columns.emplace_back(m, params);
  }
  std::ostringstream o;
  for (std::size_t i = 0; i < header.size(); ++i) o << (i ? "," : "") << csvField(header[i]);
  o << '\n';
  for (const ComparisonRow& row : t.rows) {
    o << csvField(row.dataset) << ',' << csvField(row.point_cloud_set) << ',' << csvField(row.dataset_hash);
    if (!t.mixed.empty()) o << ",yes";
    o << ',' << csvField(t.units[std::size_t(&row - t.rows.data())]);
    for (const auto& [m, params] : columns) {
      const auto best = row.best(m);
      const bool base = m == t.baseline;
      o << ',' << (best ? csvNumber(best->auc) : "") << ',' << (base ? "" : csvNumber(row.improvementPercent(m, t.baseline)))
        << ',' << (best ? csvField(t.names[best->file]) : "");
      const nlohmann::json fields = best ? parameterFields(*best, t.files) : nlohmann::json::object();
      for (const auto& p : params) o << ',' << (fields.contains(p) ? csvNumber(fields.at(p).get<double>()) : "");
    }
    o << '\n';
  }
  return o.str();
}

// As the LaTeX: display names, numbers right-aligned (a data set's name is the user's and stays as it is).
std::string markdownTables(const ComparisonTables& t) {
  const std::size_t name_columns = 2;  // data set, pcs
  std::string out = mixedNote(t) + "Best AUC per set, and the improvement over " + displayNameOf(t.baseline) +
                    " in percent:\n\n" + markdown(withDisplayNames(perSetCells(t), t.methods, name_columns),
                                                   name_columns);
  if (!t.statistics.empty()) {
    const Cells statistics = withDisplayNames(statisticsCells(t.statistics, t.baseline), t.methods, 0);
    out += "\n" + mixedNote(t) + "Statistics against " + displayNameOf(t.baseline) + " (docs/statistics.md):\n\n" +
           markdown(statistics, statistics[0].size());
    const std::vector<std::string> bases = verdictBases(t.statistics);
    if (!bases.empty()) out += "\nVerdicts:\n\n";
    for (const std::string& line : bases)  // the methods by the names the tables above show
      out += "- " + withDisplayNames(line, t.methods) + "\n";
  }
  return out;
}

std::string latexTables(const ComparisonTables& t) {
  std::string out = "% occsweep compare --latex: needs \\usepackage{booktabs}, \\usepackage{graphicx} and "
                    "\\usepackage{array}; with \\usepackage[T1]{fontenc} every character of a name shows as typed\n" +
                    latexPerSet(perSetCells(t), t,
                                mixedNote(t) + "Best AUC per set, and (%) the improvement over " +
                                    displayNameOf(t.baseline) + " in percent");
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
  const std::vector<std::string> bases = verdictBases(t.statistics);
  if (!bases.empty()) out += "\\begin{itemize}\n";
  for (const std::string& line : bases)  // the methods by the names the tables above show
    out += "  \\item " + latexEscaped(withDisplayNames(line, t.methods)) + "\n";
  if (!bases.empty()) out += "\\end{itemize}\n";
  return out;
}

}  // namespace occsweep::cli
