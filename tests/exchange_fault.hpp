// A file system that refuses to put things back, for the tests of what occsweep does when an exchange it must undo
// cannot be undone (docs/io.md, "Ownership"). Included by one test program's one source file: its
// definitions of renameat2(2) and rename(2) take the place of the C library's in that program, so the library's
// own calls reach them; disarmed, they pass every call on unchanged.
#pragma once

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream>

namespace occsweep::test {

/// The RENAME_EXCHANGE calls still let through before one fails with EIO (after which every call passes again);
/// -1: none fails.
inline std::atomic<int> exchanges_before_failure{-1};
/// While true, rename(2) fails with EIO.
inline std::atomic<bool> rename_fails{false};

/// Whether the file system of `dir` exchanges two names in one step (renameat2 RENAME_EXCHANGE): where it does not,
/// occsweep takes another path, and the tests of the exchange back have nothing to test.
inline bool exchangeSupported(const std::filesystem::path& dir) {
  const std::filesystem::path a = dir / ".exchange-probe-a", b = dir / ".exchange-probe-b";
  std::ofstream(a) << 'a';
  std::ofstream(b) << 'b';
  const bool supported = ::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0;
  std::error_code ec;
  std::filesystem::remove(a, ec);
  std::filesystem::remove(b, ec);
  return supported;
}

/// Arms the fault for one scope: the `allowed`-th exchange after this fails, and rename(2) too when `and_rename`.
struct ExchangeFault {
  ExchangeFault(int allowed, bool and_rename) {
    exchanges_before_failure = allowed;
    rename_fails = and_rename;
  }
  ~ExchangeFault() {
    exchanges_before_failure = -1;
    rename_fails = false;
  }
  ExchangeFault(const ExchangeFault&) = delete;
  ExchangeFault& operator=(const ExchangeFault&) = delete;
};

}  // namespace occsweep::test

extern "C" int renameat2(int olddirfd, const char* oldpath, int newdirfd, const char* newpath, unsigned int flags) {
  using Real = int (*)(int, const char*, int, const char*, unsigned int);
  static const auto real = reinterpret_cast<Real>(::dlsym(RTLD_NEXT, "renameat2"));
  if (real == nullptr) std::abort();  // no C library's renameat2 to pass calls on to
  auto& left = occsweep::test::exchanges_before_failure;
  if ((flags & RENAME_EXCHANGE) != 0 && left >= 0 && left-- == 0) {
    errno = EIO;
    return -1;
  }
  return real(olddirfd, oldpath, newdirfd, newpath, flags);
}

extern "C" int rename(const char* oldpath, const char* newpath) {
  using Real = int (*)(const char*, const char*);
  static const auto real = reinterpret_cast<Real>(::dlsym(RTLD_NEXT, "rename"));
  if (real == nullptr) std::abort();
  if (occsweep::test::rename_fails) {
    errno = EIO;
    return -1;
  }
  return real(oldpath, newpath);
}
