// compare's terminal statistics, CSV and Markdown (compare_tables.hpp), and the reading and line wrapping they share.
#include "compare_tables.hpp"

#include <algorithm>
#include <sstream>
#include <string_view>

#include "compare_cells.hpp"
#include "method_style.hpp"
#include "occsweep/sweeps/csv_text.hpp"
#include "occsweep/sweeps/results_verify.hpp"

namespace occsweep::cli {
namespace {

// A Markdown table cell (or list item) that CommonMark with GitHub's tables shows as the text itself (names come from
// users' files): the characters that open something inside a cell backslash-escaped ('|' ends the cell; '*', '_',
// '~', '`', '<', '&', '[', ']' start emphasis, strikethrough, code, HTML, entities and links; '\\' escapes), a line
// break as a space (it would end the row). docs/statistics.md, "In occsweep compare".
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

// The notes as a list, each item the text itself.
std::string markdownItems(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += "- " + markdownCell(line) + "\n";
  return out;
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

std::string csvTable(const ComparisonTables& t) {
  // Columns: every method's, and every parameter any of its best maps has.
  std::vector<std::string> header{"dataset", "point_cloud_set", "dataset_hash"};
  if (!t.mixed.empty()) header.push_back("mixed_settings");  // every row: compared with --allow-mixed
  header.insert(header.end(), {"unit", "truth", "coverage_warning"});
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
    o << ',' << csvField(t.units[std::size_t(&row - t.rows.data())]) << ',' << truthModeName(t.truth) << ','
      << csvField(coverageWarningOf(row, t.files));
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
                                                   name_columns) +
                    "\n" + markdownItems(truthNotes(t));
  if (!t.statistics.empty()) {
    const Cells statistics = withDisplayNames(statisticsCells(t.statistics, t.baseline), t.methods, 0);
    out += '\n';  // apart: g++ 12 warns wrongly (-Wrestrict) on "\n" + a string here
    out += mixedNote(t) + "Statistics against " + displayNameOf(t.baseline) + " (docs/statistics.md):\n\n" +
           markdown(statistics, statistics[0].size());
    const std::vector<std::string> bases = verdictBases(t.statistics);
    if (!bases.empty()) out += "\nVerdicts:\n\n";
    for (const std::string& line : bases)  // the methods by the names the tables above show
      out += "- " + withDisplayNames(line, t.methods) + "\n";
  }
  return out;
}

}  // namespace occsweep::cli
