// The JSON inputs (json_input.hpp): bounded by size before they are parsed, checked for keys given twice in one pass
// of events.
#include <set>
#include <utility>
#include <vector>

#include "occsweep/core/limits.hpp"
#include "occsweep/eval/json_input.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/json_prefix.hpp"

namespace occsweep {

nlohmann::json parseJsonText(std::string_view text, const std::filesystem::path& file) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for a number like 1e999
    throw DataError(file, "", std::string("not valid JSON: ") + e.what());
  }
}

namespace {

using nlohmann::json;

// A key given twice in one object, or a syntax error: a DataError naming the file (and the key's path). Events only,
// nothing built: nlohmann's parser with a callback scans the whole parent array at every object's end, so that a
// JSON file of 300,000 objects in one array took minutes.
class UniqueKeys : public JsonEvents {
 public:
  explicit UniqueKeys(const std::filesystem::path& file) : file_(file) {}
  bool start_object(std::size_t) override {
    std::string path = objects_.empty() ? "" : objects_.back().first;
    if (!objects_.empty()) path += (path.empty() ? "" : ".") + last_key_;
    objects_.emplace_back(std::move(path), std::set<std::string>{});
    return true;
  }
  bool end_object() override {
    objects_.pop_back();
    return true;
  }
  bool key(json::string_t& key) override {
    if (!objects_.back().second.insert(key).second) {
      const std::string& at = objects_.back().first;
      throw DataError(file_, at.empty() ? key : at + "." + key,
                      "key given twice in one object (JSON would keep only the last): give each key once");
    }
    last_key_ = key;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const json::exception& e) override {
    throw DataError(file_, "", std::string("not valid JSON: ") + e.what());
  }

 private:
  const std::filesystem::path& file_;
  std::vector<std::pair<std::string, std::set<std::string>>> objects_;  // path and keys of each open object
  std::string last_key_;
};

}  // namespace

nlohmann::json parseJsonTextUniqueKeys(std::string_view text, const std::filesystem::path& file) {
  UniqueKeys check(file);
  (void)json::sax_parse(text, &check);
  return parseJsonText(text, file);
}

nlohmann::json readJsonFile(const std::filesystem::path& file) {
  // A key given twice is refused: JSON keeps the last, another reader (a script, a person) the first, so two readers
  // would see two files (docs/results-format.md).
  return parseJsonTextUniqueKeys(readJsonBytes(file), file);
}

std::string readJsonBytes(const std::filesystem::path& file) {
  requireRegularFile(file);
  // nlohmann's tree takes up to 18 times a file's bytes (a 30 MB file took 543 MB): refused by its size before a
  // byte is read (docs/robustness.md, "Limits and non-regular files").
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  checkLimit(file.string() + ": bytes of JSON", ec ? 0 : size, limits().json_bytes, "--max-json-bytes");
  return readFileBytes(file, limits().json_bytes);
}

}  // namespace occsweep
