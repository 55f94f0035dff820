// Small parsers of the plan options: grid specs, command templates, output kinds.
#include <charconv>
#include <stdexcept>
#include <utility>

#include "occsweep/sweeps/cluster_plan.hpp"

namespace occsweep {

PlanGrid parsePlanGrid(const std::string& text) {
  PlanGrid g;
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("--grid '" + text + "': " + why + " (expected NAME[:SHARDS[:grouped]])");
  };
  std::vector<std::string> parts;
  // A grid may be a path: split from the right, at most two fields.
  std::string rest = text;
  for (int i = 0; i < 2; ++i) {
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos) break;
    parts.insert(parts.begin(), rest.substr(colon + 1));
    rest = rest.substr(0, colon);
  }
  g.name = rest;
  if (g.name.empty()) throw bad("empty grid name");
  if (parts.size() == 2) {
    if (parts[1] != "grouped") throw bad("third field must be 'grouped'");
    g.grouped = true;
  }
  if (!parts.empty()) {
    const std::string& n = parts[0];
    const auto [end, error] = std::from_chars(n.data(), n.data() + n.size(), g.shards);
    if (n.empty() || error != std::errc() || end != n.data() + n.size() || g.shards == 0)
      throw bad("shards must be a whole number from 1 to " + std::to_string(UINT64_MAX));
  }
  return g;
}

std::string expandTemplate(const std::string& text, const std::map<std::string, std::string>& values) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '{') {
      out += text[i];
      continue;
    }
    const auto close = text.find('}', i);
    if (close == std::string::npos) throw std::invalid_argument("template '" + text + "': '{' without '}'");
    const std::string key = text.substr(i + 1, close - i - 1);
    const auto it = values.find(key);
    if (it == values.end()) {
      std::string known;
      for (const auto& [k, v] : values) known += " {" + k + "}";
      throw std::invalid_argument("template '" + text + "': unknown {" + key + "}; known:" + known);
    }
    out += it->second;
    i = close;
  }
  return out;
}

std::vector<std::string> splitArgs(const std::string& text) {
  std::vector<std::string> args;
  std::string cur;
  for (char c : text) {
    if (c == ' ' || c == '\t') {
      if (!cur.empty()) args.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) args.push_back(cur);
  return args;
}

void parseStageValues(const std::vector<std::string>& given, const std::string& flag, std::string& every,
                      std::map<std::string, std::string>& per_stage) {
  bool every_given = false;
  for (const std::string& text : given) {
    const auto eq = text.find('=');
    const std::string stage = eq == std::string::npos ? "" : text.substr(0, eq);
    const std::string value = eq == std::string::npos ? text : text.substr(eq + 1);
    if (value.empty() || (eq != std::string::npos && stage.empty()))
      throw std::invalid_argument(flag + " '" + text + "': expected VALUE for every stage or STAGE=VALUE");
    if (stage.empty() ? std::exchange(every_given, true) : !per_stage.emplace(stage, value).second)
      throw std::invalid_argument(flag + " '" + text + "': " + (stage.empty() ? "every stage's" : "stage " + stage + "'s") +
                                  " value is given twice");
    if (stage.empty()) every = value;
  }
}

std::string stageMem(const SlurmOptions& o, const std::string& stage) {
  const auto it = o.stage_mem.find(stage);
  return it == o.stage_mem.end() ? o.mem : it->second;
}

std::string stageTime(const SlurmOptions& o, const std::string& stage) {
  const auto it = o.stage_time.find(stage);
  return it == o.stage_time.end() ? o.time : it->second;
}

const ClusterStage& stageNamed(const ClusterPlan& plan, const std::string& name) {
  for (const auto& s : plan.stages)
    if (s.name == name) return s;
  throw std::out_of_range("no stage '" + name + "' in the plan");
}

const char* kindName(OutputKind k) {
  switch (k) {
    case OutputKind::Results: return "results";
    case OutputKind::Comparison: return "comparison";
    case OutputKind::Dataset: return "dataset";
    case OutputKind::Exists: return "exists";
  }
  return "exists";
}

OutputKind kindFromName(const std::string& name) {
  for (auto k : {OutputKind::Results, OutputKind::Comparison, OutputKind::Dataset, OutputKind::Exists})
    if (name == kindName(k)) return k;
  throw std::invalid_argument("'" + name + "': expected results, comparison, dataset or exists");
}

}  // namespace occsweep
