// The one error type of data input: it names the file, the field or line, and the rule broken.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace occsweep {

class DataError : public std::runtime_error {
 public:
  DataError(const std::filesystem::path& file, const std::string& where, const std::string& rule)
      : std::runtime_error(file.string() + (where.empty() ? "" : ": " + where) + ": " + rule) {}
};

}  // namespace occsweep
