// The JSON inputs of bounded_read.hpp: bounded by size before they are parsed, checked for keys given twice in one
// pass of events, and an output's "format" field read from its first bytes alone.
#include <fstream>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "occsweep/core/limits.hpp"
#include "occsweep/eval/bounded_read.hpp"

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

// Every SAX event accepted, a syntax error ending the parse: what the readers below override a few of.
struct JsonEvents : json::json_sax_t {
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(json::number_integer_t) override { return true; }
  bool number_unsigned(json::number_unsigned_t) override { return true; }
  bool number_float(json::number_float_t, const json::string_t&) override { return true; }
  bool string(json::string_t&) override { return true; }
  bool binary(json::binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(json::string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t, const std::string&, const json::exception&) override { return false; }
};

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

// The top-level object's "format" string, the parse stopped as soon as it is read.
class TopLevelFormat : public JsonEvents {
 public:
  std::optional<std::string> format;
  bool start_object(std::size_t) override {
    ++depth_;
    return true;
  }
  bool end_object() override { return --depth_ > 0; }
  bool start_array(std::size_t) override { return depth_++ > 0; }  // a top-level array has no format
  bool end_array() override {
    --depth_;
    return true;
  }
  bool key(json::string_t& key) override {
    at_format_ = depth_ == 1 && key == "format";
    return true;
  }
  bool string(json::string_t& value) override {
    if (!at_format_ || depth_ != 1) return true;
    format = value;
    return false;
  }

 private:
  int depth_ = 0;
  bool at_format_ = false;
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

std::optional<std::string> jsonFormatField(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(std::filesystem::status(file, ec))) return std::nullopt;  // a FIFO would wait
  std::ifstream in(file, std::ios::binary);
  std::string prefix(kJsonFormatPrefixBytes, '\0');
  in.read(prefix.data(), std::streamsize(prefix.size()));
  prefix.resize(std::size_t(in.gcount()));
  TopLevelFormat found;
  (void)json::sax_parse(prefix, &found);
  return found.format;
}

}  // namespace occsweep
