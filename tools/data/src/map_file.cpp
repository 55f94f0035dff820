#include "occsweep/data/map_file.hpp"

#include <fstream>
#include <string>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/json_prefix.hpp"
#include "occsweep/io/output_target.hpp"

namespace occsweep {

namespace fs = std::filesystem;

bool isMapSettingsFile(const fs::path& file) {
  if (!fs::is_regular_file(file)) return false;  // a FIFO would block the read below
  if (jsonOutput("", kMapSettingsFormat).is_own(file)) return true;
  try {  // written before the format field existed: occsweep's keys, in a few hundred bytes (never read past them)
    if (fs::file_size(file) > kJsonFormatPrefixBytes) return false;
    std::ifstream in(file);
    const auto j = nlohmann::json::parse(in);
    return j.is_object() && j.contains("method") && j.contains("parameters") && j.contains("dataset_hash");
  } catch (const std::exception&) {
    return false;
  }
}

ReplaceableOutput mapOutput() {
  return {"map (.ot with its .ot.json)", [](const fs::path& ot) {
            if (!fs::is_regular_file(fs::symlink_status(ot))) return false;  // a FIFO would block the read below
            std::ifstream in(ot, std::ios::binary);
            std::string head(21, '\0');
            in.read(head.data(), std::streamsize(head.size()));
            return in && head == "# Octomap OcTree file" && isMapSettingsFile(ot.string() + ".json");
          }};
}

// liboctomap writes .ot whatever the name; a .bt name would hold .ot bytes that octovis and readBinary misread.
void checkMapTarget(const fs::path& out, bool force) {
  const std::string name = out.string();
  if (out.extension() == ".bt")
    throw std::invalid_argument("--out " + name + ": .bt keeps only occupied/free, not the log-odds the " +
                                "evaluation reads: write .ot (octovis opens it; octomap's convert_octree makes a .bt)");
  if (out.extension() != ".ot")
    throw std::invalid_argument("--out " + name + ": must end in .ot (the map is written as OctoMap .ot, log-odds kept)");
  requireCompanionName(out, ".json");
  checkOutputTarget(out, force, mapOutput());
  // occsweep's own settings without their map are what a kill between the two renames leaves (the .ot.json is
  // renamed first): a leftover of occsweep's, replaced like a stale temporary (docs/robustness.md).
  const bool orphan_settings = !fs::exists(fs::symlink_status(out)) && isMapSettingsFile(name + ".json");
  checkOutputTarget(name + ".json", force || orphan_settings, jsonOutput("map settings (.ot.json)", kMapSettingsFormat));
}

void writeMapFile(const octomap::OcTree& tree, const nlohmann::json& settings, const fs::path& out) {
  OutputFile map_file(out);
  if (!tree.write(map_file.stream())) throw OutputError(out.string() + ": liboctomap could not write the map");
  OutputFile settings_file(out.string() + ".json");
  settings_file.stream() << settings.dump(1) << '\n';
  OutputFile::commitTogether({&map_file, &settings_file});  // neither when either fails or was taken meanwhile
}

}  // namespace occsweep
