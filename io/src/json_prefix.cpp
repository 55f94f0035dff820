// An output's "format" field read from its first bytes alone (json_prefix.hpp).
#include "occsweep/io/json_prefix.hpp"

#include <fstream>

namespace occsweep {
namespace {

using nlohmann::json;

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
