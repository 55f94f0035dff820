// Untrusted files read within a bound: only regular files, only up to a size, a first line only up to a length;
// every failure a DataError naming the file (docs/io.md, "Reading within a bound").
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "occsweep/io/data_error.hpp"

namespace occsweep {

/// Largest file readFileBytes reads whole unless told otherwise.
inline constexpr std::uint64_t kMaxImportFileBytes = std::uint64_t(4) << 30;

/// Every reader of an input file calls this first: DataError naming the file and what it is when it
/// is not a regular file (missing, a folder, a FIFO, which would make a reader wait forever, a socket, a device,
/// a symlink loop or a dangling link), so that no reader hangs or reports "file is missing" for a folder.
void requireRegularFile(const std::filesystem::path& file);

/// The whole file; DataError when requireRegularFile refuses it, it is unreadable, or larger than `max_bytes`.
[[nodiscard]] std::string readFileBytes(const std::filesystem::path& file,
                                        std::uint64_t max_bytes = kMaxImportFileBytes);

/// The first line of `file` (without its line break), read from a regular file only (a link is followed: callers
/// that must refuse one check it) and at most `max_bytes` of it: nothing when the file is not a regular file, cannot
/// be read, or has no line break within `max_bytes` (a marker
/// line occsweep writes is short; a file of gigabytes without a line break is never read whole).
[[nodiscard]] std::optional<std::string> readFirstLine(const std::filesystem::path& file, std::size_t max_bytes);

}  // namespace occsweep
