// run-local: the same plan without Slurm, so a laptop and a cluster share one path.
#include <cerrno>
#include <chrono>
#include <iostream>
#include <map>
#include <sys/wait.h>

#include "occsweep/sweeps/cluster_slurm.hpp"

namespace occsweep {
namespace fs = std::filesystem;

std::size_t runLocal(const ClusterPlan& plan, const fs::path& plan_dir, int jobs) {
  const fs::path dir = fs::absolute(plan_dir);  // tasks start in it, and logs open after that chdir
  if (jobs < 1) throw std::invalid_argument("-j must be at least 1");
  fs::create_directories(dir / "logs");
  // A plan also submitted to Slurm: its live tasks would write the same outputs as ours.
  if (const auto subs = readSubmissions(dir); !subs.empty()) {
    std::size_t live = 0;
    for (const auto& row : planStatus(plan, dir, querySlurm(subs), subs))
      for (const auto& t : row) live += t.state == TaskState::Running || t.state == TaskState::Pending;
    if (live)
      throw std::runtime_error(std::to_string(live) + " tasks of the plan are running or pending on Slurm: wait for "
                               "them (`cluster status DIR --wait`) or scancel them first");
  }
  // Otherwise what is done is what is on disk.
  const auto torun = tasksToRun(plan, planStatus(plan, dir, {}, {}));
  std::size_t failed = 0;
  for (std::size_t s = 0; s < plan.stages.size(); ++s) {
    const ClusterStage& stage = plan.stages[s];
    const auto& ids = torun[s];
    if (ids.empty()) {
      std::cerr << "stage " << stage.name << ": all " << stage.tasks.size() << " tasks done\n";
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    auto last_print = start;
    std::map<pid_t, std::uint64_t> running;
    std::size_t next = 0, finished = 0, stage_failed = 0;
    auto reap = [&] {
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, 0);
      if (pid < 0) {
        if (errno == EINTR) return;
        throw std::runtime_error("waitpid failed");
      }
      const auto it = running.find(pid);
      if (it == running.end()) return;
      const ClusterTask& t = stage.tasks[it->second];
      ++finished;
      const int code = exitCodeOf(status);
      std::string why = code == 0 ? checkOutput(t, dir) : "exit code " + std::to_string(code);
      if (!why.empty()) {
        ++stage_failed;
        std::cerr << "stage " << stage.name << ": task " << t.index << " (" << t.label << ") failed: " << why
                  << "; log " << (dir / "logs" / ("local-" + stage.name + "-" + std::to_string(t.index) + ".log")).string()
                  << '\n';
      }
      // A line every few seconds, not one per task: paper-scale stages have hundreds.
      const auto now = std::chrono::steady_clock::now();
      if (finished == ids.size() || now - last_print > std::chrono::seconds(5)) {
        std::cerr << "stage " << stage.name << ": " << finished << "/" << ids.size() << " tasks finished\n";
        last_print = now;
      }
      running.erase(it);
    };
    for (auto t : ids) {  // outputs rewritten now must not count as done meanwhile
      std::error_code ec;
      if (fs::is_regular_file(dir / stage.tasks[t].output, ec)) fs::remove(dir / stage.tasks[t].output, ec);
    }
    while (next < ids.size() || !running.empty()) {
      while (next < ids.size() && running.size() < std::size_t(jobs)) {
        const ClusterTask& t = stage.tasks[ids[next]];
        const fs::path log = dir / "logs" / ("local-" + stage.name + "-" + std::to_string(t.index) + ".log");
        fs::remove(log);
        running[spawnLogged(t.argv, dir, log)] = t.index;
        ++next;
      }
      reap();
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "stage " << stage.name << ": " << ids.size() - stage_failed << " of " << ids.size()
              << " tasks succeeded in " << secs << " s\n";
    failed += stage_failed;
    if (stage_failed) {  // like afterok: later stages would read missing inputs
      std::cerr << "stopping: later stages need this one\n";
      break;
    }
  }
  return failed;
}

}  // namespace occsweep
