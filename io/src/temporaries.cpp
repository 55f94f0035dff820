// This process's temporaries, removed on errors, SIGINT, SIGTERM and SIGHUP, and the children an interrupt ends first
// (docs/io.md, "Outputs and --force").
#include "occsweep/io/temporaries.hpp"
#include "occsweep/io/output_target.hpp"
#include "occsweep/io/ownership.hpp"
#include "output_registry.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <set>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace occsweep {
namespace fs = std::filesystem;
using namespace io_detail;

std::mutex& io_detail::registryMutex() {
  static auto* m = new std::mutex;
  return *m;
}

void runWithoutInterruptCleaning(const std::function<void()>& step) {
  const std::lock_guard lock(registryMutex());
  step();
}

namespace {

// The device and inode of the entry at `path` itself (not what a link there points to); {0, 0} when it cannot be read.
std::pair<dev_t, ino_t> entryNumbers(const fs::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {0, 0};
  return {st.st_dev, st.st_ino};
}

// The live temporaries of this process, each with the entry it was made as: removed (on an error, an interrupt, or
// by its owner's destructor) only while that entry stands at its name. A user's entry is there for a moment when an
// exchange that put occsweep's output in place is being undone (a partial output's, sweep_partial.cpp), and is never
// occsweep's to remove.
std::map<fs::path, std::pair<dev_t, ino_t>>& liveTemporaries() {
  static auto* made = new std::map<fs::path, std::pair<dev_t, ino_t>>;
  return *made;
}

// What an interrupt prints before the exit (setInterruptMessage); read by the cleaner under the registry's lock.
std::string& interruptMessage() {
  static auto* message = new std::string;
  return *message;
}

// Children runChild waits for (child_process.hpp): ended before their temporaries are removed.
std::set<pid_t>& children() {
  static auto* pids = new std::set<pid_t>;
  return *pids;
}

int interrupt_pipe[2] = {-1, -1};

std::atomic<int> g_interrupt_signal{0};  // lock-free: written in the handler, read by other threads
static_assert(std::atomic<int>::is_always_lock_free);

// Async-signal-safe: a flag and write(2), errno kept for the interrupted code. The cleaning happens in an ordinary
// thread (cleanOnInterrupt).
extern "C" void forwardSignal(int sig) {
  const int saved_errno = errno;
  g_interrupt_signal.store(sig);
  const unsigned char byte = static_cast<unsigned char>(sig);
  [[maybe_unused]] const ssize_t n = ::write(interrupt_pipe[1], &byte, 1);
  errno = saved_errno;
}

// Writes `text` whole to stderr, as far as it goes.
void writeToStderr(const std::string& text) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(2, text.data() + done, text.size() - done);
    if (n <= 0 && errno != EINTR) break;
    done += n > 0 ? std::size_t(n) : 0;
  }
}

// Removes every registered temporary, prints `message` and exits with `status`; the caller holds the registry's lock
// (cleanOnInterrupt, exitRemovingTemporaries).
[[noreturn]] void removeTemporariesAndExit(int status, const std::string& message) {
  // A child still writing (a figure script) would recreate a temporary removed under it: it ends first.
  for (const pid_t pid : children()) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
  }
  for (const auto& [path, made] : liveTemporaries())
    if (made == entryNumbers(path)) removeTemporaryEntry(path);  // another entry at its name (or none) is a user's
  writeToStderr(message);
  ::_exit(status);
}

void cleanOnInterrupt() {
  unsigned char sig = 0;
  for (;;) {
    const ssize_t n = ::read(interrupt_pipe[0], &sig, 1);
    if (n == 1) break;
    if (n == 0 || errno != EINTR) return;  // the pipe is gone: no signal can be forwarded any more
  }
  // The lock is held until _exit: a commit (which takes it too) cannot rename a temporary into place after, or
  // while, its files are removed here (a SIGTERM'd `scene` once renamed a folder holding only manifest.json).
  registryMutex().lock();
  removeTemporariesAndExit(128 + sig, interruptMessage());
}

}  // namespace

// Under the registry's lock, which an interrupt's cleaner holds until _exit (cleanOnInterrupt): made after the lock
// is released, the entry could appear just after the cleaner's removal and outlive the exit.
int io_detail::registerAndCreate(const fs::path& path, TemporaryKind kind) {
  std::lock_guard lock(registryMutex());
  const int fd = kind == TemporaryKind::File
                     ? ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666)
                     : ::mkdir(path.c_str(), 0777);
  if (fd < 0) return fd;
  liveTemporaries()[path] = entryNumbers(path);
  return fd;
}

void io_detail::unregisterTemporaryLocked(const fs::path& path) { liveTemporaries().erase(path); }

void io_detail::unregisterTemporary(const fs::path& path) {
  std::lock_guard lock(registryMutex());
  unregisterTemporaryLocked(path);
}

namespace {

// Whether the entry this run made as its temporary `path` still stands there; the caller holds the registry's lock.
bool madeEntryStands(const fs::path& path) {
  const auto made = liveTemporaries().find(path);
  return made != liveTemporaries().end() && made->second == entryNumbers(path);
}

}  // namespace

bool io_detail::temporaryReplaced(const fs::path& path) {
  const auto made = liveTemporaries().find(path);
  return made != liveTemporaries().end() && made->second != entryNumbers(path);
}

bool io_detail::isMadeEntry(const fs::path& path) {
  std::lock_guard lock(registryMutex());
  return madeEntryStands(path);
}


RegisteredTemporary::RegisteredTemporary(const fs::path& target, TemporaryKind kind) {
  const fs::path t = outputTarget(target);
  reportLeftoverTemporaries(t);
  path_ = temporaryNameFor(t);
  const int fd = registerAndCreate(path_, kind);
  if (fd < 0) failWrite(t, errno);
  if (kind == TemporaryKind::File) fd_ = fd;
}

RegisteredTemporary::~RegisteredTemporary() {
  if (fd_ >= 0) ::close(fd_);
  if (!kept_ && isMadeEntry(path_)) removeTemporaryEntry(path_);
  unregisterTemporary(path_);
}

void RegisteredTemporary::keep() {
  unregisterTemporary(path_);
  kept_ = true;
}

void setInterruptMessage(std::string message) {
  std::lock_guard lock(registryMutex());
  interruptMessage() = std::move(message);
}

int interruptSignalReceived() { return g_interrupt_signal.load(); }

void exitRemovingTemporaries(int status, const std::string& message) {
  // A thread that failed holding the lock (this one, inside a commit) never releases it: after a second the exit
  // leaves the temporaries to the next run, as a SIGKILL does (removeStaleTemporaries).
  for (int waited_ms = 0; !registryMutex().try_lock(); waited_ms += 10) {
    if (waited_ms >= 1000) {
      writeToStderr(message);
      ::_exit(status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  removeTemporariesAndExit(status, message);
}

pid_t forkRegisteredChild() {
  // Under the registry's lock, which the interrupt cleaner takes first: it either sees the child, or has begun
  // and this process is about to exit (no child is started then).
  std::lock_guard lock(registryMutex());
  if (interruptSignalReceived() != 0) return -1;
  const pid_t pid = ::fork();
  if (pid > 0) children().insert(pid);
  return pid;
}

void unregisterChildProcess(pid_t pid) {
  std::lock_guard lock(registryMutex());
  children().erase(pid);
}

void removeTemporariesOnInterrupt() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (::pipe2(interrupt_pipe, O_CLOEXEC) != 0) return;
    std::thread(cleanOnInterrupt).detach();
    struct sigaction action {};
    action.sa_handler = forwardSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &action, nullptr);
    std::signal(SIGXFSZ, SIG_IGN);  // past `ulimit -f`, write(2) fails with EFBIG: a message instead of a core
  });
}

}  // namespace occsweep
