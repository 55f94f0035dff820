// The plan's files: DIR/plan.json (the manifest of every shard) and one sbatch script per stage.
#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <sys/vfs.h>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/child_process.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/sweeps/cluster_plan.hpp"
#include "occsweep/sweeps/results.hpp"
#include "occsweep/eval/json_input.hpp"

namespace occsweep {
namespace {

using nlohmann::json;
constexpr const char* kPlanFormat = "occsweep-cluster-plan";

json workJson(const ExpectedWork& w) {
  json group = nullptr;
  if (w.group) group = {w.group->index, w.group->count, w.group->seed};
  json j = toJson(w.map);
  j["group"] = group;
  j["truth"] = truthModeName(w.truth);
  return j;
}

json taskJson(const ClusterTask& t) {
  json j = {{"index", t.index}, {"label", t.label}, {"argv", t.argv}, {"inputs", t.inputs},
            {"output", t.output}, {"kind", kindName(t.kind)}};
  if (t.kind != OutputKind::Results) return j;
  j["expect"] = {{"grid", t.expect_grid}, {"shard", {t.expect_shard, t.expect_shards}}};
  if (t.expect_work) j["expect"]["work"] = workJson(*t.expect_work);
  return j;
}

json planJson(const ClusterPlan& p) {
  json stages = json::array();
  for (const auto& s : p.stages) {
    json tasks = json::array();
    for (const auto& t : s.tasks) tasks.push_back(taskJson(t));
    stages.push_back({{"name", s.name}, {"after", s.after}, {"tasks", tasks}});
  }
  const auto& o = p.slurm;
  return {{"format", kPlanFormat}, {"version", 1}, {"experiment", p.experiment}, {"occsweep", p.occsweep},
          {"slurm", {{"cpus_per_task", o.cpus_per_task}, {"mem", o.mem}, {"time", o.time},
                     {"partition", o.partition}, {"account", o.account}, {"extra", o.extra},
                     {"stage_mem", o.stage_mem}, {"stage_time", o.stage_time}, {"setup", o.setup},
                     {"array_throttle", o.array_throttle}, {"max_array_size", o.max_array_size}}},
          {"stages", stages}};
}

/// A value of `j` at `key`, or a runtime_error naming the file and the field.
template <class T>
T field(const json& j, const std::string& key, const std::string& file, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw std::runtime_error(file + ": " + where + key + ": missing");
  try {
    return j.at(key).get<T>();
  } catch (const json::exception&) {
    throw std::runtime_error(file + ": " + where + key + ": wrong type");
  }
}

/// A value of `j` at `key`, or `otherwise` when the key is missing (a plan written before the field existed).
template <class T>
T optionalField(const json& j, const std::string& key, const std::string& file, const std::string& where,
                T otherwise) {
  return j.is_object() && j.contains(key) ? field<T>(j, key, file, where) : otherwise;
}

/// Whether plan.json at `manifest` is occsweep's own plan, proven by its own `format` field; what it is otherwise.
std::optional<std::string> notOurPlan(const std::filesystem::path& manifest) {
  try {
    const json j = readJsonFile(manifest);
    if (j.is_object() && j.contains("format") && j.at("format") == kPlanFormat) return std::nullopt;
    return "not an occsweep plan (no \"format\": \"" + std::string(kPlanFormat) + "\")";
  } catch (const std::exception& e) {
    return std::string("not an occsweep plan (") + e.what() + ")";
  }
}

ExpectedWork parseWork(const json& w, const std::string& file, const std::string& where) {
  ExpectedWork work;
  const json group = field<json>(w, "group", file, where);
  if (!group.is_null()) {
    const auto g = field<std::vector<std::uint64_t>>(w, "group", file, where);
    if (g.size() != 3 || g[0] >= g[1])
      throw std::runtime_error(file + ": " + where + "group: expected [I, N, SEED] with I < N");
    work.group = SweepSelection::Group{g[0], g[1], g[2]};
  }
  work.map = parseMapSettings(w, [&](const std::string& key, const std::string& rule) {
    throw std::runtime_error(file + ": " + where + key + ": " + rule);
  });
  try {
    work.truth = parseTruthMode(field<std::string>(w, "truth", file, where));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file + ": " + where + "truth: " + e.what());
  }
  return work;
}

ClusterPlan parsePlan(const json& j, const std::string& file) {
  if (field<std::string>(j, "format", file, "") != kPlanFormat)
    throw std::runtime_error(file + ": format: expected \"" + std::string(kPlanFormat) + "\"");
  if (field<int>(j, "version", file, "") != 1) throw std::runtime_error(file + ": version: expected 1");
  ClusterPlan p;
  p.experiment = field<std::string>(j, "experiment", file, "");
  p.occsweep = field<std::string>(j, "occsweep", file, "");
  const json s = field<json>(j, "slurm", file, "");
  p.slurm = SlurmOptions{};
  p.slurm.cpus_per_task = field<int>(s, "cpus_per_task", file, "slurm.");
  p.slurm.mem = field<std::string>(s, "mem", file, "slurm.");
  p.slurm.time = field<std::string>(s, "time", file, "slurm.");
  p.slurm.partition = field<std::string>(s, "partition", file, "slurm.");
  p.slurm.account = field<std::string>(s, "account", file, "slurm.");
  p.slurm.extra = field<std::vector<std::string>>(s, "extra", file, "slurm.");
  using StageValues = std::map<std::string, std::string>;
  p.slurm.stage_mem = optionalField<StageValues>(s, "stage_mem", file, "slurm.", {});
  p.slurm.stage_time = optionalField<StageValues>(s, "stage_time", file, "slurm.", {});
  p.slurm.setup = optionalField<std::vector<std::string>>(s, "setup", file, "slurm.", {});
  for (const char* key : {"array_throttle", "max_array_size"})  // not 2.7, not -1: whole numbers only
    if (s.contains(key) && !s.at(key).is_number_unsigned())
      throw std::runtime_error(file + ": slurm." + key + ": expected a whole number >= 0");
  p.slurm.array_throttle = optionalField<std::uint64_t>(s, "array_throttle", file, "slurm.", 0);
  p.slurm.max_array_size = optionalField<std::uint64_t>(s, "max_array_size", file, "slurm.", 0);
  for (const auto& sj : field<json>(j, "stages", file, "")) {
    ClusterStage st{field<std::string>(sj, "name", file, "stages[]."),
                    field<std::vector<std::string>>(sj, "after", file, "stages[]."), {}};
    const std::string where = "stages[" + st.name + "].tasks[].";
    for (const auto& tj : field<json>(sj, "tasks", file, "stages[].")) {
      ClusterTask t;
      t.index = field<std::uint64_t>(tj, "index", file, where);
      if (t.index != st.tasks.size()) throw std::runtime_error(file + ": " + where + "index: not in order");
      t.label = field<std::string>(tj, "label", file, where);
      t.argv = field<std::vector<std::string>>(tj, "argv", file, where);
      if (t.argv.empty()) throw std::runtime_error(file + ": " + where + "argv: empty");
      t.inputs = field<std::vector<std::string>>(tj, "inputs", file, where);
      t.output = field<std::string>(tj, "output", file, where);
      if (const auto broken = brokenPlanOutputRule(t.output))
        throw std::runtime_error(file + ": " + where + "output: " + *broken);
      try {
        t.kind = kindFromName(field<std::string>(tj, "kind", file, where));
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(file + ": " + where + "kind: " + e.what());
      }
      if (t.kind == OutputKind::Results) {
        const json e = field<json>(tj, "expect", file, where);
        t.expect_grid = field<std::string>(e, "grid", file, where + "expect.");
        const auto shard = field<std::vector<std::uint64_t>>(e, "shard", file, where + "expect.");
        if (shard.size() != 2 || shard[0] >= shard[1])
          throw std::runtime_error(file + ": " + where + "expect.shard: expected [I, N] with I < N");
        t.expect_shard = shard[0];
        t.expect_shards = shard[1];
        if (e.contains("work")) t.expect_work = parseWork(e.at("work"), file, where + "expect.work.");
      }
      st.tasks.push_back(std::move(t));
    }
    p.stages.push_back(std::move(st));
  }
  try {
    checkSlurmOptions(p);  // a hand-edited plan.json writes no other script than `cluster plan` would
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file + ": slurm: " + e.what());
  }
  return p;
}


}  // namespace

namespace {

void writeSbatchOptions(std::ostream& s, const SlurmOptions& o, const std::string& mem, const std::string& time,
                        const std::string& stage) {
  s << "#SBATCH --job-name=occsweep-" << stage << "\n#SBATCH --cpus-per-task=" << o.cpus_per_task << '\n';
  if (!mem.empty()) s << "#SBATCH --mem=" << mem << '\n';
  if (!time.empty()) s << "#SBATCH --time=" << time << '\n';
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << '\n';
  if (!o.account.empty()) s << "#SBATCH --account=" << o.account << '\n';
  for (const auto& e : o.extra) s << "#SBATCH " << e << '\n';
  // Requeue after node failure is safe: every output is written atomically and a sweep resumes.
  s << "#SBATCH --requeue\n";
}

void writeTaskCases(std::ostream& s, const ClusterStage& stage, const std::string& id) {
  for (const auto& t : stage.tasks) {
    s << "  " << t.index << ")";
    for (const auto& a : t.argv) s << ' ' << shellWord(a);
    s << " ;;\n";
  }
  s << "  *) echo \"stage " << stage.name << " has no task " << id << "\" >&2; exit 2 ;;\nesac\n";
}

}  // namespace

std::string sbatchScript(const ClusterPlan& plan, const ClusterStage& stage) {
  const auto& o = plan.slurm;
  std::ostringstream s;
  s << "#!/bin/bash\n# occsweep cluster plan, stage " << stage.name << ": " << stage.tasks.size()
    << " tasks, one occsweep command each. Submitted by `occsweep cluster submit|resubmit`, which adds\n"
    << "# --array (only the tasks to run, in arrays within MaxArraySize: task = array index + OCCSWEEP_TASK_OFFSET),\n"
    << "# --chdir (the plan folder), --output and --dependency=afterok.\n";
  writeSbatchOptions(s, o, stageMem(o, stage.name), stageTime(o, stage.name), stage.name);
  s << "set -eo pipefail\n"
    << "task=$(( ${SLURM_ARRAY_TASK_ID:?not run as a job array task} + ${OCCSWEEP_TASK_OFFSET:-0} ))\n"
    << "echo \"occsweep cluster plan: stage " << stage.name << ", task $task\" >&2  # logs are named by array index\n";
  // Set-up lines before `set -u`, which environment-module scripts break; after `set -e`, so a failing one stops the task.
  if (!o.setup.empty()) s << "# set-up (cluster plan --setup)\n";
  for (const auto& line : o.setup) s << line << '\n';
  s << "set -u\ncase \"$task\" in\n";
  writeTaskCases(s, stage, "$task");
  return s.str();
}

std::string sbatchScriptBeforeOffsets(const ClusterPlan& plan, const ClusterStage& stage) {
  const auto& o = plan.slurm;
  std::ostringstream s;
  s << "#!/bin/bash\n# occsweep cluster plan, stage " << stage.name << ": " << stage.tasks.size()
    << " tasks, one occsweep command each. Submitted by `occsweep cluster submit|resubmit`, which adds\n"
    << "# --array (only the tasks to run), --chdir (the plan folder), --output and --dependency=afterok.\n";
  writeSbatchOptions(s, o, o.mem, o.time, stage.name);
  s << "set -euo pipefail\ncase \"${SLURM_ARRAY_TASK_ID:?not run as a job array task}\" in\n";
  writeTaskCases(s, stage, "$SLURM_ARRAY_TASK_ID");
  return s.str();
}

std::optional<std::string> localFileSystemOf(const std::filesystem::path& path) {
  struct statfs info {};
  if (::statfs(path.c_str(), &info) != 0) return std::nullopt;
  // Magic numbers of <linux/magic.h> (and zfs's), for the file systems that never span machines.
  static const std::map<unsigned long, std::string> local = {
      {0xEF53, "ext2/3/4"}, {0x58465342, "xfs"}, {0x9123683E, "btrfs"}, {0x01021994, "tmpfs"},
      {0x794C7630, "overlay"}, {0x2FC12FC1, "zfs"}, {0x4D44, "vfat"}, {0x5346544E, "ntfs"}};
  const auto it = local.find(static_cast<unsigned long>(info.f_type) & 0xFFFFFFFFUL);
  if (it == local.end()) return std::nullopt;
  return it->second;
}

std::optional<std::string> brokenPlanOutputRule(const std::string& output) {
  const std::filesystem::path p(output);
  bool up = false;
  for (const auto& part : p) up = up || part == "..";
  if (output.empty() || p.is_absolute() || up)
    return "must be a relative path inside the plan folder (not absolute, no '..'): run-local and resubmit "
           "write and remove it";
  return std::nullopt;
}

namespace {

// --force replaces occsweep's own earlier plan only, as everywhere (docs/cluster.md); a user's plan.json stays.
// An output the old plan's task wrote, at the path a task of the new plan with another command writes, would pass
// that task's check and count as done (a sweep's results under other settings): refused, naming it, before the plan
// is replaced (docs/cluster.md, "The plan").
void refuseStaleOutputs(const std::filesystem::path& dir, const ClusterPlan& old, const json& plan) {
  std::map<std::string, json> argv_of;  // the new plan's command per output
  for (const json& stage : plan.at("stages"))
    for (const json& task : stage.at("tasks")) argv_of[task.at("output").get<std::string>()] = task.at("argv");
  for (const ClusterStage& stage : old.stages)
    for (const ClusterTask& task : stage.tasks) {
      std::error_code ec;
      const auto now = argv_of.find(task.output);
      if (now == argv_of.end() || now->second == json(task.argv) ||
          !std::filesystem::exists(std::filesystem::symlink_status(dir / task.output, ec)))
        continue;
      throw std::runtime_error((dir / task.output).string() + ": an output of the plan being replaced, which the new "
                               "plan's task there (another command) would take as done: remove it (and the other "
                               "outputs of the old plan), or choose another --out (nothing changed)");
    }
}

// The occsweep plan already in `dir` (nothing when there is none), read once for every check below.
std::optional<ClusterPlan> replacedPlan(const std::filesystem::path& dir, const json& plan, bool force) {
  namespace fs = std::filesystem;
  const fs::path manifest = dir / "plan.json";
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(manifest, ec))) return std::nullopt;
  if (const auto why = notOurPlan(manifest))
    throw std::runtime_error(manifest.string() + ": " + *why + ": refused, with or without --force (nothing "
                             "changed); choose another --out");
  const ClusterPlan old = readPlan(dir);
  if (!force && planJson(old) != plan)
    throw std::runtime_error(manifest.string() + ": a different plan is already there (--force replaces it, or "
                             "choose another --out)");
  refuseStaleOutputs(dir, old, plan);
  // Proven occsweep's plan: its commit may replace it, and nothing that takes its place meanwhile (output_file.hpp).
  checkOutputTarget(manifest, true, jsonOutput("cluster plan", kPlanFormat));
  return old;
}

// The scripts occsweep may have written for `stage_name` in the plan `old`: today's, and the one of an occsweep before
// array offsets (none when it has no such stage).
std::vector<std::string> ownScripts(const std::optional<ClusterPlan>& old, const std::string& stage_name) {
  if (old)
    for (const ClusterStage& st : old->stages)
      if (st.name == stage_name) return {sbatchScript(*old, st), sbatchScriptBeforeOffsets(*old, st)};
  return {};
}

// The plan's own files and folders are never reached through a symbolic link: a link is the user's entry, and
// writing through one would put the plan's files elsewhere (docs/io.md, "Ownership").
void refuseLinks(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  auto refuseLink = [](const fs::path& entry) {
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(entry, ec)))
      throw std::runtime_error(entry.string() + ": is a symbolic link: occsweep never writes through or replaces "
                               "one, even with --force (nothing changed); remove it, or choose another --out");
  };
  for (const fs::path& entry : {dir / "plan.json", dir / "slurm", dir / "logs"}) refuseLink(entry);
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(dir / "slurm", ec)))
    for (const auto& script : fs::directory_iterator(dir / "slurm", ec)) refuseLink(script.path());
}

// A stage's script is written where nothing stands, or over the very bytes occsweep wrote for the plan there: a
// user's file, or occsweep's script edited by hand (a `module load` line), is never replaced, even with --force
// (docs/cluster.md, "The plan").
void refuseOtherScripts(const std::filesystem::path& dir, const ClusterPlan& plan,
                        const std::optional<ClusterPlan>& old) {
  namespace fs = std::filesystem;
  for (const ClusterStage& st : plan.stages) {
    const fs::path script = dir / "slurm" / (st.name + ".sbatch");
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(script, ec))) continue;
    const std::vector<std::string> own = ownScripts(old, st.name);
    const ReplaceableOutput own_script{"Slurm script of the plan", [own](const fs::path& file) {
                                         std::error_code ec;
                                         if (!fs::is_regular_file(fs::symlink_status(file, ec))) return false;
                                         const std::uint64_t size = fs::file_size(file, ec);
                                         if (ec || std::none_of(own.begin(), own.end(), [&](const std::string& o) {
                                               return o.size() == size;
                                             }))
                                           return false;
                                         const std::string bytes = readFileBytes(file);
                                         return std::find(own.begin(), own.end(), bytes) != own.end();
                                       }};
    if (!own_script.is_own(script))
      throw std::runtime_error(script.string() + ": not the script occsweep wrote for the plan there (a file of "
                               "yours, or the plan's script edited by hand): never replaced, even with --force "
                               "(nothing changed); move it away, or choose another --out");
    checkOutputTarget(script, true, own_script);  // its commit replaces this very file, nothing put there meanwhile
  }
}

/// The files and folders one writePlan made, removed one by one on failure: a folder goes only when empty, so an
/// entry someone else put there meanwhile stays, and so does every folder on its way (docs/io.md,
/// "Ownership": a folder tree is never removed whole).
class MadeEntries {
 public:
  /// create_directories, remembering each folder it creates.
  void folders(const std::filesystem::path& dir) {
    const std::vector<std::filesystem::path> missing = missingFolders(dir);  // innermost first
    std::filesystem::create_directories(dir);
    entries_.insert(entries_.end(), missing.rbegin(), missing.rend());
  }
  void file(const std::filesystem::path& f) { entries_.push_back(f); }
  /// Newest first; fs::remove leaves a folder that is not empty.
  void undo() {
    std::error_code ec;
    for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) std::filesystem::remove(*it, ec);
  }

 private:
  std::vector<std::filesystem::path> entries_;
};

}  // namespace

void writePlan(const ClusterPlan& plan, const std::filesystem::path& dir, bool force) {
  namespace fs = std::filesystem;
  const fs::path manifest = dir / "plan.json";
  const json j = planJson(plan);
  for (const auto& st : plan.stages)
    for (const auto& t : st.tasks)
      if (const auto broken = brokenPlanOutputRule(t.output))
        throw std::invalid_argument("task " + st.name + "[" + std::to_string(t.index) + "] output " + t.output + ": " +
                                    *broken);
  refuseLinks(dir);
  const std::optional<ClusterPlan> old = replacedPlan(dir, j, force);
  refuseOtherScripts(dir, plan, old);
  MadeEntries made;
  try {
    made.folders(dir / "slurm");
    made.folders(dir / "logs");
    for (const auto& st : plan.stages) {
      const fs::path script = dir / "slurm" / (st.name + ".sbatch");
      const bool existed = fs::exists(fs::symlink_status(script));
      writeFileAtomically(script, sbatchScript(plan, st));
      if (!existed) made.file(script);
      fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
    }
    writeJsonAtomically(j, manifest);  // last: a plan folder with plan.json is complete
  } catch (const fs::filesystem_error& e) {  // the plan folder named, not the library's "filesystem error"
    made.undo();
    throw std::runtime_error(dir.string() + ": cannot create the plan folder: " + e.code().message() +
                             (e.code() == std::errc::not_a_directory ? " (a file is in the way; choose another --out)"
                                                                      : ""));
  } catch (...) {
    made.undo();  // a failed write (a full disk) leaves none of the plan files and folders it made
    throw;
  }
}

ClusterPlan readPlan(const std::filesystem::path& dir) {
  const std::string file = (dir / "plan.json").string();
  if (!std::filesystem::exists(file)) throw std::runtime_error(file + ": cannot open (not a plan folder?)");
  return parsePlan(readJsonFile(file), file);
}

}  // namespace occsweep
