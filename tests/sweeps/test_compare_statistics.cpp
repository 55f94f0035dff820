// The statistics of `occsweep compare` (docs/statistics.md): identical methods show no gain, no budget gap and an
// interval containing zero; a uniform gain is called a gain; leave-one-out selection against a brute-force loop;
// the CSV reads back (Python's csv module) into the numbers of --json; the LaTeX table is the golden one.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/sweeps/compare_statistics.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {

// A results file of `method` for point cloud set `set` of data set `dataset`: one map per AUC.
ResultsFile syntheticResults(const std::string& method, const std::string& dataset, int set,
                             const std::vector<double>& aucs) {
  ResultsFile f;
  f.header.method = method;
  // Built with append: g++ 12 warns wrongly (-Wrestrict) on some chains of string operator+.
  f.header.grid_name = std::string(method).append("-grid");
  f.header.grid_hash = std::string(method).append("-hash");
  f.header.dataset_name = std::string(dataset).append("/pcs-").append(std::to_string(set));
  f.header.dataset_hash = std::string(dataset).append(std::to_string(set));
  f.header.parameters = {{"p_max", "p_min", "x"}, {false, false, false}};
  for (std::size_t m = 0; m < aucs.size(); ++m) {
    MapResult r;
    r.map_index = m;
    r.params.values = {980000, 20000, Fixed(m) * 1000};
    r.area.anchored = r.area.observed = aucs[m];
    f.maps.push_back(r);
  }
  f.complete = true;
  return f;
}

// Sets of several data sets, each with a grid of random AUCs per method; `shift` is added to method b's.
std::vector<ResultsFile> syntheticComparison(std::uint64_t seed, std::size_t maps_a, std::size_t maps_b, double shift,
                                             bool b_copies_a, int datasets = 4, int sets_per_dataset = 3) {
  SplitMix64 rng(seed);
  std::vector<ResultsFile> files;
  for (int d = 0; d < datasets; ++d)
    for (int set = 0; set < sets_per_dataset; ++set) {
      std::vector<double> a, b;
      for (std::size_t m = 0; m < maps_a; ++m) a.push_back(0.5 + 0.3 * rng.uniform());
      for (std::size_t m = 0; m < maps_b; ++m) b.push_back(b_copies_a ? a[m] + shift : 0.5 + 0.3 * rng.uniform() + shift);
      const std::string dataset = std::string("d").append(std::to_string(d));
      files.push_back(syntheticResults("base", dataset, set, a));
      files.push_back(syntheticResults("other", dataset, set, b));
    }
  return files;
}

const MethodStatistics& statisticsOf(const std::vector<MethodStatistics>& all, const std::string& method) {
  for (const auto& s : all)
    if (s.method == method) return s;
  FAIL("no statistics of " << method);
  return all.front();
}

// One method's statistics against "base", by value (the vector they come in is a temporary).
MethodStatistics statisticsFor(const std::vector<ResultsFile>& files, const std::string& method) {
  return statisticsOf(compareStatistics(compareBest(files), files, statisticsAgainst("base")), method);
}

// The golden builtin sweeps (results/builtin) as data set `index`, written to `dir` for `occsweep compare`: OctoMap's
// best map raised (voxels moved from FN to TP at one threshold, from FP to TN at another) until k-NN's best improves
// on it by `percent` to within 2e-4 %; with `nested`, k-NN's map 0 takes that map's counts, so that k-NN's results
// hold OctoMap's best (grids that nest), in k-NN's file or in a second k-NN file (a copy with map 0 changed). Real
// results files, checked as any other: the command under test reads them.
enum class Nested { No, InItsFile, InASecondFile };
void writeGoldenDataset(const fs::path& dir, int index, double percent, Nested nested = Nested::No) {
  const fs::path golden = test::sourceTree() / "results" / "builtin";
  ResultsFile octomap = readResults(golden / "octomap-opt.json"), knn = readResults(golden / "knn-opt.json");
  auto bestOf = [](ResultsFile& f) -> MapResult& {
    return *std::max_element(f.maps.begin(), f.maps.end(),
                             [](const MapResult& a, const MapResult& b) { return a.area.anchored < b.area.anchored; });
  };
  MapResult& best = bestOf(octomap);
  const double target = bestOf(knn).area.anchored / (1.0 + percent / 100.0);
  std::vector<ThresholdResult> closest = best.thresholds;
  for (std::size_t i = 0; i < best.thresholds.size(); ++i)
    for (std::size_t j = 0; j < best.thresholds.size(); ++j)
      for (std::uint64_t to_tp = 0; to_tp <= std::min<std::uint64_t>(best.thresholds[i].counts.fn, 40); ++to_tp)
        for (std::uint64_t to_tn = 0; to_tn <= std::min<std::uint64_t>(best.thresholds[j].counts.fp, 60); ++to_tn) {
          std::vector<ThresholdResult> t = best.thresholds;
          t[i].counts.fn -= to_tp, t[i].counts.tp += to_tp;
          t[j].counts.fp -= to_tn, t[j].counts.tn += to_tn;
          if (std::fabs(mapArea(t).anchored - target) < std::fabs(mapArea(closest).anchored - target)) closest = t;
        }
  REQUIRE(std::fabs(mapArea(closest).anchored / target - 1.0) < 2e-6);
  best.thresholds = closest;
  best.area = mapArea(closest);
  ResultsFile second = knn;
  if (nested != Nested::No) {
    ResultsFile& holder = nested == Nested::InItsFile ? knn : second;
    for (std::size_t t = 0; t < closest.size(); ++t) holder.maps[0].thresholds[t].counts = closest[t].counts;
    holder.maps[0].area = best.area;
  }
  for (ResultsFile* f : {&octomap, &knn, &second}) {
    if (f == &second && nested != Nested::InASecondFile) continue;
    f->header.dataset_name = "room-" + std::to_string(index);
    f->header.dataset_hash = std::string(16 - std::to_string(index + 10).size(), 'a') + std::to_string(index + 10);
    // Each copy stands for a room of its own: its own scene (docs/statistics.md, "Verdicts", rule 1).
    f->header.point_cloud_set["provenance"] = {{"scene", f->header.dataset_hash}};
    writeResults(*f, dir / (f->header.method + (f == &second ? "-second-" : "-") + std::to_string(index) + ".json"));
  }
}

// `occsweep compare` (the binary under test) over the data sets written to `dir`: k-NN's entry of --json's statistics.
nlohmann::json compareKnnStatistics(const fs::path& dir, const std::string& flags = "") {
  const test::CommandResult r = test::runIn(dir, "compare *.json --json c.json" + flags);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const nlohmann::json out = nlohmann::json::parse(test::bytesOf(dir / "c.json"));
  for (const nlohmann::json& m : out.at("statistics"))
    if (m.at("method") == "knn") return m;
  FAIL("no statistics of knn");
  return nullptr;
}

}  // namespace

TEST_CASE("identical methods: no gain, an interval at zero, no budget gap, the same cross-validated score") {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const auto files = syntheticComparison(seed, 15, 15, 0.0, true);
    const auto rows = compareBest(files);
    const auto all = compareStatistics(rows, files, statisticsAgainst("base"));
    REQUIRE(all.size() == 2);
    CHECK(all[0].method == "base");
    const MethodStatistics& s = statisticsOf(all, "other");
    CHECK(s.sets == 12);
    CHECK(s.ties == 12);
    REQUIRE(s.improvement_percent);
    CHECK(s.improvement_percent->contains(0.0));
    CHECK(s.optima.verdict.text == "tie (equal on all 4 data sets)");
    CHECK(s.cross_validated.verdict.text == "tie (equal on all 4 data sets)");
    CHECK(s.sets_holding_baseline_best == 12);  // its grid is the baseline's
    CHECK_FALSE(s.wilcoxon);  // every difference is zero
    CHECK(s.sign->p_value == 1.0);
    CHECK_FALSE(s.budget.first_above_baseline);  // a curve never passes its own grid's best
    CHECK(s.leave_one_set_out.score == all[0].leave_one_set_out.score);
    CHECK(s.leave_one_dataset_out.score == all[0].leave_one_dataset_out.score);
  }
}

TEST_CASE("a method better on every map by 0.05: a gain over eight data sets, too few to tell over two or four") {
  const auto eight = syntheticComparison(7, 15, 15, 0.05, true, 8);
  const MethodStatistics s = statisticsFor(eight, "other");
  CHECK(s.better == 24);
  CHECK(s.datasets == 8);
  CHECK(s.improvement_percent->lower > 0);
  CHECK(s.optima.verdict.text == "gain");
  CHECK(s.cross_validated.verdict.text == "gain");
  REQUIRE(s.optima.test);
  CHECK(s.optima.test->p_value == Approx(2.0 / 256.0));  // 8 of 8 data sets positive, two-sided
  CHECK(s.optima.verdict.basis.find("n = 8 data sets") != std::string::npos);
  CHECK(s.sign->p_value == Approx(2.0 / (1 << 24)));     // the per-set sign test stays, as description
  CHECK(s.budget.first_above_baseline.has_value());
  // --json carries each data set's value beside the verdict, so that a reader can recompute it.
  const nlohmann::json j = toJson(compareStatistics(compareBest(eight), eight, statisticsAgainst("base")),
                                  statisticsAgainst("base"));
  for (const nlohmann::json& m : j)
    if (m.at("method") == "other") {
      const nlohmann::json& per = m.at("optima_over_datasets").at("per_dataset");
      REQUIRE(per.size() == 8);
      for (std::size_t i = 0; i < 8; ++i) {
        CHECK(per[i].at("dataset").get<std::string>() == s.optima.datasets[i]);
        CHECK(per[i].at("improvement_percent").get<double>() == s.optima.per_dataset[i]);
      }
      CHECK(m.at("cross_validated_over_datasets").at("per_dataset").size() == 8);
    }
  for (const int datasets : {2, 4}) {
    const auto few = syntheticComparison(7, 15, 15, 0.05, true, datasets);
    const MethodStatistics f = statisticsFor(few, "other");
    INFO(datasets << " data sets");
    CHECK(f.improvement_percent->lower > 0);  // the per-set interval excludes 0: today's "gain"
    CHECK(f.optima.verdict.kind == stats::VerdictKind::TooFew);
    CHECK(f.optima.verdict.text == (datasets == 2 ? "too few data sets to tell (n = 2; the smallest p possible is 0.5)"
                                                  : "too few data sets to tell (n = 4; the smallest p possible is 0.125)"));
  }
}

TEST_CASE("four point cloud sets of one data set are one sample, not four") {
  const auto files = syntheticComparison(3, 10, 10, 0.05, true, 1, 4);
  const MethodStatistics s = statisticsFor(files, "other");
  CHECK(s.sets == 4);
  CHECK(s.better == 4);
  CHECK(s.datasets == 1);
  CHECK(s.optima.per_dataset.size() == 1);
  CHECK(s.optima.verdict.text == "too few data sets to tell (n = 1; the smallest p possible is 1)");
  CHECK(s.cross_validated.verdict.text == "too few data sets to tell (n = 1; holding one out needs at least 2)");
}

TEST_CASE("sets of one name and several contents are one data set, and named as pooled") {
  // Two contents both named builtin-O (two built-in scenes, or one recording under two regions): one data set, the
  // cautious reading, and pooledDatasetNames names it for compare's note.
  auto files = syntheticComparison(5, 10, 10, 0.05, true, 2, 1);
  for (ResultsFile& f : files) f.header.dataset_name = "builtin-O";
  const MethodStatistics s = statisticsFor(files, "other");
  CHECK(s.sets == 2);
  CHECK(s.datasets == 1);
  CHECK(pooledDatasetNames(compareBest(files)) == std::vector<std::string>{"builtin-O"});
  // Generated sets of one data set differ in content by design: not reported.
  CHECK(pooledDatasetNames(compareBest(syntheticComparison(5, 10, 10, 0.05, true, 1, 3))).empty());
  // Only a pcs-NNNN part makes a set of a data set (old: any '/' did, silently): foo/bar and foo/baz are two.
  auto slashed = syntheticComparison(5, 10, 10, 0.05, true, 2, 1);
  for (std::size_t i = 0; i < slashed.size(); ++i) slashed[i].header.dataset_name = i < 2 ? "foo/bar" : "foo/baz";
  CHECK(statisticsFor(slashed, "other").datasets == 2);
  CHECK(pooledDatasetNames(compareBest(slashed)).empty());
  // A data set given whole and with sets of its own is pooled, and named.
  auto mixed = syntheticComparison(5, 10, 10, 0.05, true, 1, 2);
  for (std::size_t i = 0; i < 2; ++i) mixed[i].header.dataset_name = "d0";
  CHECK(statisticsFor(mixed, "other").datasets == 1);
  CHECK(pooledDatasetNames(compareBest(mixed)) == std::vector<std::string>{"d0"});
}

TEST_CASE("units from provenance: data sets sharing an input, truth and poses, or a scene are one scene") {
  // Eight data sets of one set each, "other" better on all; their recorded provenance decides the units.
  auto files = syntheticComparison(7, 10, 10, 0.05, true, 8, 1);
  const std::vector<nlohmann::json> provenance = {
      {{"inputs", {"a1", "a2"}}},                                       // d0: joined to d1 by a2 and d1 to d2 by a3
      {{"inputs", {"a2", "a3"}}},
      {{"inputs", {"a3"}}},
      {{"inputs", {"b1"}}, {"poses", {"p"}}, {"truth", {"t"}}},       // d3, d4: one truth and one pose file
      {{"inputs", {"b2"}}, {"poses", {"p"}}, {"truth", {"t"}}},
      {{"inputs", {"b3"}}, {"poses", {"p"}}, {"truth", {"t2"}}},      // d5: another truth, a scene of its own
      {{"scene", "s"}},                                                  // d6, d7: one generated scene
      {{"scene", "s"}}};
  for (ResultsFile& f : files) f.header.point_cloud_set["provenance"] = provenance[std::size_t(f.header.dataset_name[1] - '0')];
  const SampleUnits units = sampleUnits(compareBest(files), UnitRule::Provenance);
  CHECK(units.noun == "scenes");
  CHECK(units.without_provenance.empty());
  const std::set<std::string> distinct(units.of_row.begin(), units.of_row.end());
  CHECK(distinct == std::set<std::string>{"d0 + 2 more", "d3 + d4", "d5", "d6 + d7"});
  const MethodStatistics s = statisticsFor(files, "other");
  CHECK(s.datasets == 8);
  CHECK(s.scenes == 4);
  CHECK(s.optima.per_dataset.size() == 4);
  CHECK(s.optima.verdict.text == "too few scenes to tell (n = 4; the smallest p possible is 0.125)");
  CHECK(s.optima.verdict.basis.find("8 data sets over 4 scenes (scenes by content hashes") != std::string::npos);

  // Declared by names, each data set is a unit again: eight, a gain.
  CompareStatisticsOptions by_name = statisticsAgainst("base");
  by_name.units = UnitRule::Names;
  const MethodStatistics named = statisticsOf(compareStatistics(compareBest(files), files, by_name), "other");
  CHECK(named.scenes == 8);
  CHECK(named.optima.verdict.text == "gain");
  CHECK(named.optima.verdict.basis.find("units declared by --units names") != std::string::npos);

  // A data set without provenance (an older occsweep's) is a unit by its name, and the basis says it is assumed.
  files[0].header.point_cloud_set.erase("provenance");
  files[1].header.point_cloud_set.erase("provenance");
  const SampleUnits mixed = sampleUnits(compareBest(files), UnitRule::Provenance);
  CHECK(mixed.without_provenance == std::vector<std::string>{"d0"});
  CHECK(std::set<std::string>(mixed.of_row.begin(), mixed.of_row.end()).size() == 5);  // d0 apart, d1 + d2 joined
  CHECK(mixed.declaration.find("1 data set has no content hashes recorded (made by an older occsweep): each name "
                               "assumed a scene of its own") != std::string::npos);
}

TEST_CASE("results without provenance (an older occsweep's) keep the data set as the unit, and say it is assumed") {
  const auto files = syntheticComparison(3, 10, 10, 0.05, true, 8, 1);
  const MethodStatistics s = statisticsFor(files, "other");
  CHECK(s.scenes == 8);
  CHECK(s.optima.verdict.text == "gain");
  CHECK(s.optima.verdict.basis.find("n = 8 data sets") != std::string::npos);
  CHECK(s.optima.verdict.basis.find("8 data sets (units: data set names, assumed independent: no content "
                                    "hashes recorded (made by an older occsweep))") != std::string::npos);
}

TEST_CASE("Holm's correction runs over every method compared with the baseline") {
  // Six data sets of one set each, "up" better on all six (exact p = 2/64 = 0.03125 < 0.05): a gain alone; beside two
  // methods equal to the baseline (p = 1 each) Holm multiplies it by 3 (0.094): six data sets cannot show a gain in
  // a family of three, and the verdict says so with the bound after the correction.
  auto files = syntheticComparison(5, 10, 10, 0.05, true, 6, 1);
  for (auto& f : files)
    if (f.header.method == "other") f.header.method = "up";
  auto alone = compareStatistics(compareBest(files), files, statisticsAgainst("base"));
  CHECK(statisticsOf(alone, "up").optima.verdict.text == "gain");
  CHECK(statisticsOf(alone, "up").optima.holm_p == Approx(0.03125));
  const std::size_t n = files.size();
  for (std::size_t i = 0; i < n; ++i)
    if (files[i].header.method == "base")
      for (const char* twin : {"same-1", "same-2"}) {
        ResultsFile copy = files[i];
        copy.header.method = twin;
        files.push_back(copy);
      }
  const auto three = compareStatistics(compareBest(files), files, statisticsAgainst("base"));
  const MethodStatistics& up = statisticsOf(three, "up");
  CHECK(up.optima.family == 3);
  CHECK(up.optima.holm_family == "the 3 optima verdicts of same-1, same-2, up against base");
  CHECK(up.cross_validated.holm_family == "the 3 cross-validated verdicts of same-1, same-2, up against base");
  CHECK(up.optima.holm_p == Approx(3 * 0.03125));
  CHECK(up.optima.verdict.text ==
        "too few data sets to tell (n = 6; the smallest p possible is 0.0938 after Holm's correction over 3 comparisons)");
  CHECK(up.optima.verdict.basis.find("Holm-adjusted over 3 comparisons 0.0938") != std::string::npos);
  CHECK(statisticsOf(three, "same-1").optima.verdict.kind == stats::VerdictKind::Tie);
}

TEST_CASE("a difference of -0.004 % on every set with a rejecting test: a loss below the smallest effect") {
  auto files = syntheticComparison(9, 12, 12, 0.0, true, 10, 2);
  for (auto& f : files)
    if (f.header.method == "other")
      for (auto& m : f.maps) m.area.anchored = m.area.observed = m.area.anchored * (1.0 - 4e-5);
  const MethodStatistics s = statisticsFor(files, "other");
  CHECK(s.worse == 20);
  REQUIRE(s.optima.interval);
  CHECK(s.optima.interval->upper < 0);  // excludes 0 and the test rejects: the verdict says so (issue 44)
  CHECK(s.optima.interval->estimate == Approx(-0.004).epsilon(1e-6));
  CHECK(s.optima.verdict.kind == stats::VerdictKind::Loss);
  CHECK(s.optima.verdict.text.find("loss, below the smallest effect of 0.1 % (sign test: the 90% interval of the "
                                   "median [") == 0);
  REQUIRE(s.optima.verdict.equivalence);
  CHECK(s.optima.verdict.equivalence->upper < 0.1);
  CHECK(s.optima.verdict.equivalence->lower > -0.1);
  CHECK(s.sets_holding_baseline_best == 0);
}

TEST_CASE("leave-one-set-out and leave-one-data-set-out scores equal a brute-force loop") {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const auto files = syntheticComparison(seed, 6, 9, 0.0, false);
    const auto all = compareStatistics(compareBest(files), files, statisticsAgainst("base"));
    for (const char* method : {"base", "other"}) {
      std::vector<std::vector<double>> sets;  // per set, every map's AUC
      std::vector<int> dataset;
      for (std::size_t i = 0; i < files.size(); ++i)
        if (files[i].header.method == method) {
          sets.emplace_back();
          for (const auto& m : files[i].maps) sets.back().push_back(m.area.anchored);
          dataset.push_back(int(sets.size() - 1) / 3);
        }
      // Brute force: for each held-out group, the map with the best mean over the other groups (first on ties),
      // scored on the group; groups are sets, or data sets with each map's AUC averaged over their sets.
      auto bruteForce = [](const std::vector<std::vector<double>>& groups) {
        double score = 0;
        for (std::size_t out = 0; out < groups.size(); ++out) {
          std::size_t chosen = 0;
          double best = -1;
          for (std::size_t m = 0; m < groups[out].size(); ++m) {
            double sum = 0;
            for (std::size_t g = 0; g < groups.size(); ++g)
              if (g != out) sum += groups[g][m];
            if (sum / double(groups.size() - 1) > best) best = sum / double(groups.size() - 1), chosen = m;
          }
          score += groups[out][chosen];
        }
        return score / double(groups.size());
      };
      std::vector<std::vector<double>> datasets(4, std::vector<double>(sets[0].size(), 0.0));
      for (std::size_t i = 0; i < sets.size(); ++i)
        for (std::size_t m = 0; m < sets[i].size(); ++m) datasets[std::size_t(dataset[i])][m] += sets[i][m] / 3.0;
      const MethodStatistics& s = statisticsOf(all, method);
      INFO(method << " seed " << seed);
      CHECK(s.leave_one_set_out.score == Approx(bruteForce(sets)).epsilon(1e-12));
      CHECK(s.leave_one_dataset_out.score == Approx(bruteForce(datasets)).epsilon(1e-12));
      CHECK(s.leave_one_set_out.groups == 12);
      CHECK(s.leave_one_dataset_out.groups == 4);
    }
  }
}

TEST_CASE("the cross-validated verdict rests on leave one data set out, one value per data set") {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const auto files = syntheticComparison(seed, 6, 6, 0.01, false, 7, 3);
    const MethodStatistics s = statisticsFor(files, "other");
    // Brute force: per data set, each method's map chosen by the best mean over the other data sets' sets (data
    // sets weigh equally: the mean of their means), scored by its mean over the held-out data set's sets.
    auto heldOut = [&](const char* method, int out) {
      std::vector<std::vector<double>> mean(7, std::vector<double>(6, 0.0));
      for (const auto& f : files)
        if (f.header.method == method) {
          const int d = f.header.dataset_name[1] - '0';
          for (std::size_t m = 0; m < 6; ++m) mean[std::size_t(d)][m] += f.maps[m].area.anchored / 3.0;
        }
      std::size_t chosen = 0;
      double best = -1;
      for (std::size_t m = 0; m < 6; ++m) {
        double sum = 0;
        for (int d = 0; d < 7; ++d)
          if (d != out) sum += mean[std::size_t(d)][m];
        if (sum / 6.0 > best) best = sum / 6.0, chosen = m;
      }
      return mean[std::size_t(out)][chosen];
    };
    REQUIRE(s.cross_validated.per_dataset.size() == 7);
    for (int d = 0; d < 7; ++d) {
      const double expected = (heldOut("other", d) - heldOut("base", d)) / heldOut("base", d) * 100.0;
      INFO("seed " << seed << " data set " << d);
      CHECK(s.cross_validated.per_dataset[std::size_t(d)] == Approx(expected).epsilon(1e-9).margin(1e-12));
    }
    CHECK(s.leave_one_set_out_improvement.has_value());  // kept beside it, marked optimistic
  }
}

TEST_CASE("the statistics do not depend on the order the files are given in") {
  auto files = syntheticComparison(11, 8, 12, 0.01, false);
  const auto forward = compareStatistics(compareBest(files), files, statisticsAgainst("base"));
  std::reverse(files.begin(), files.end());
  const auto backward = compareStatistics(compareBest(files), files, statisticsAgainst("base"));
  const MethodStatistics &a = statisticsOf(forward, "other"), &b = statisticsOf(backward, "other");
  CHECK(a.improvement_percent->lower == b.improvement_percent->lower);
  CHECK(a.improvement_percent->upper == b.improvement_percent->upper);
  CHECK(a.optima.interval->lower == b.optima.interval->lower);
  CHECK(a.wilcoxon->p_value == b.wilcoxon->p_value);
}

TEST_CASE("sets of one grid with different numbers of maps (Eq. 16 groups) get no budget curve") {
  auto files = syntheticComparison(5, 6, 9, 0.0, false);
  files.back().maps.pop_back();  // the last set of "other" holds one map fewer
  const auto all = compareStatistics(compareBest(files), files, statisticsAgainst("base"));
  const MethodStatistics& s = statisticsOf(all, "other");
  CHECK(s.budget.maps == 0);
  CHECK(s.leave_one_set_out.groups == 0);
  CHECK_FALSE(s.leave_one_set_out_improvement);
  CHECK(s.cross_validated.per_dataset.empty());
  CHECK(s.cross_validated.verdict.text == "not computed (the sets differ in grid or maps, or an AUC is undefined)");
  CHECK(s.sets == 12);
}

TEST_CASE("a baseline that was not given is refused, naming the methods that were") {
  const auto files = syntheticComparison(3, 5, 5, 0.0, true);
  CHECK_THROWS_WITH(compareStatistics(compareBest(files), files, statisticsAgainst("octomap")),
                    Catch::Contains("baseline octomap") && Catch::Contains("base, other"));
}

namespace {

// The widest box pdflatex reported past the text width in `log` ("Overfull \\hbox (12.3pt too wide)"), in pt; 0 if none.
double widestOverfull(const std::string& log) {
  double widest = 0;
  const std::string mark = "Overfull \\hbox (";
  for (std::size_t at = log.find(mark); at != std::string::npos; at = log.find(mark, at + 1))
    widest = std::max(widest, std::stod(log.substr(at + mark.size())));
  return widest;
}

// `tables` (in `dir`) compiled by pdflatex in a plain article with only booktabs, graphicx and array: a PDF, no box
// wider than the text width (TeX reports each as "Overfull \\hbox" in its log) and no float taller than the page.
// And not by shrinking it out of sight: compiled without its \\resizebox, the per-set table is at most 20 % wider than
// the text width (a plain article's 345 pt), so it prints at 83 % of its size or more.
void checkFitsPlainArticle(const fs::path& dir, const std::string& tables) {
  auto compile = [&](const std::string& input) {
    std::ofstream(dir / "doc.tex", std::ios::trunc)
        << "\\documentclass{article}\n\\usepackage{booktabs}\n\\usepackage{graphicx}\n"
           "\\usepackage{array}\n\\begin{document}\n\\input{" << input << "}\n\\end{document}\n";
    const auto tex = test::runShell("cd " + dir.string() + " && pdflatex -interaction=nonstopmode -halt-on-error doc.tex");
    INFO(tex.output);
    CHECK(tex.exit_code == 0);
    CHECK(fs::file_size(dir / "doc.pdf") > 1000);
    return test::bytesOf(dir / "doc.log");
  };
  const std::string log = compile(tables);
  CHECK(log.find("Overfull \\hbox") == std::string::npos);
  CHECK(log.find("Float too large") == std::string::npos);
  std::string natural = test::bytesOf(dir / tables);
  const std::string shrink = "\\resizebox{\\ifdim\\width>\\linewidth\\linewidth\\else\\width\\fi}{!}{%";
  for (std::size_t at = natural.find(shrink); at != std::string::npos; at = natural.find(shrink))
    natural.replace(at, shrink.size(), "{%");
  std::ofstream(dir / "natural.tex", std::ios::trunc) << natural;
  const double over = widestOverfull(compile("natural.tex"));
  INFO("the tables' natural width is " << over << " pt past the text width");
  CHECK(over <= 0.2 * 345);
}

}  // namespace

TEST_CASE("compare --csv reads back with Python's csv module into the numbers of --json, and --latex is the golden table") {
  const auto dir = test::processScratch("compare-tables");
  const fs::path golden = occsweep::test::sourceTree() / "results" / "builtin";
  const std::string files = (golden / "octomap-opt.json").string() + " " + (golden / "knn-opt.json").string();
  const auto r = test::runIn(dir, "compare " + files + " --json c.json --csv c.csv --latex c.tex --markdown c.md");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("statistics against octomap") != std::string::npos);
  const char* check = R"(python3 -c "
import csv, json, sys
rows = list(csv.DictReader(open('c.csv')))
j = json.load(open('c.json'))
assert len(rows) == len(j['rows']) == 1, 'rows'
for row, jr in zip(rows, j['rows']):
    for m in ('octomap', 'knn'):
        assert float(row[m + '.auc']) == jr['methods'][m]['auc'], m
        for name, value in jr['methods'][m]['parameters'].items():
            assert float(row[m + '.' + name]) == value, name
    assert float(row['knn.improvement_percent']) == jr['methods']['knn']['improvement_percent']
    assert row['unit'] == jr['unit'] == 'builtin-O', 'unit'
    assert (row['truth'], row['coverage_warning']) == (j['truth'], '') == ('full', ''), 'truth'
print('csv equals json')
")";
  const auto py = test::runShell("cd " + dir.string() + " && " + check);
  INFO(py.output);
  CHECK(py.exit_code == 0);
  CHECK(py.output.find("csv equals json") != std::string::npos);
  // The LaTeX of the golden files is itself golden (made by this command; results/builtin/compare.tex), and it
  // compiles with booktabs where pdflatex is installed (the test command installs it: tools/setup.sh).
  CHECK(test::bytesOf(dir / "c.tex") == test::bytesOf(golden / "compare.tex"));
  if (test::runShell("command -v pdflatex").exit_code == 0) {
    checkFitsPlainArticle(dir, "c.tex");  // old: 421 pt and 1,154 pt past the text width
  } else {
    WARN("pdflatex not installed: the LaTeX table is checked against its golden text only");
  }
  // Markdown as the LaTeX: display names, the per-set numbers right-aligned.
  const std::string md = test::bytesOf(dir / "c.md");
  CHECK(md.find("| k-NN |") != std::string::npos);
  CHECK(md.find("| k-NN AUC | k-NN vs OctoMap % |") != std::string::npos);
  CHECK(md.find("|---|---|---:|---:|---:|\n") != std::string::npos);
  CHECK(md.find("| knn |") == std::string::npos);
  CHECK(md.find("- knn,") == std::string::npos);  // the verdicts under the tables name it so too
  // The truth under the per-set table, and no warning: the golden results record none.
  CHECK(md.find("|\n\n- truth: full (every truth voxel of the region counts)\n\nStatistics") != std::string::npos);
  // A table of another program's is never replaced, even with --force.
  std::ofstream(dir / "mine.csv") << "my,own,data\n";
  const auto refused = test::runIn(dir, "compare " + files + " --csv mine.csv --force");
  CHECK(refused.exit_code == 2);
  CHECK(test::bytesOf(dir / "mine.csv") == "my,own,data\n");
}

namespace {

// The results files of data set `index` in `dir` (writeGoldenDataset's) as scored under `truth`, recording
// `coverage`; the warning compare notes of them (docs/import.md, "Truth coverage and alignment"), "" for none.
std::string recordCoverage(const fs::path& dir, int index, const TruthCoverage& coverage, TruthMode truth) {
  std::string warning;
  for (const char* method : {"octomap", "knn"}) {
    const fs::path file = dir / (std::string(method) + "-" + std::to_string(index) + ".json");
    ResultsFile f = readResults(file);
    f.header.coverage = coverage, f.header.truth = truth;
    writeResults(f, file);
    warning = coverageWarning(*readResults(file).header.coverage, truth);  // at the file's resolution and s_c
  }
  return warning;
}

// Markdown's text with its backslash escapes (compare_tables.cpp, markdownCell) undone.
std::string unescapedMarkdown(const std::string& md) {
  std::string out;
  for (std::size_t i = 0; i < md.size(); ++i)
    if (!(md[i] == '\\' && i + 1 < md.size() && std::string("|*_~`<>&[]\\").find(md[i + 1]) != std::string::npos))
      out += md[i];
    else
      out += md[++i];
  return out;
}

}  // namespace

TEST_CASE("compare's --markdown, --latex and --csv state the truth and carry each truth coverage warning (issue 44)") {
  // Old binary: the terminal noted both warnings and the truth; the tables said neither, so a table pasted into a
  // paper hid that its AUCs measure the recording's coverage (or a misalignment), not the mapping.
  const fs::path dir = test::scratch("compare-truth-notes");
  for (int d = 0; d < 3; ++d) writeGoldenDataset(dir, d, 0.05 + 0.1 * d);
  TruthCoverage partial;  // a recording that sees 7 % of its truth, its points on it
  partial.truth_voxels = 13132, partial.sampled_truth = 4000, partial.observable_sampled = 269;
  partial.points = 5000, partial.points_in_region = 4000, partial.sampled_points = 2000;
  partial.median_point_distance = 0.05;
  TruthCoverage outside = partial;  // poses in the wrong convention: no point in the region
  outside.points_in_region = outside.sampled_points = 0, outside.median_point_distance = NAN;
  TruthCoverage seen = partial;  // most of it seen: nothing to warn of
  seen.observable_sampled = 3900;
  const bool pdflatex = test::runShell("command -v pdflatex").exit_code == 0;
  for (const TruthMode truth : {TruthMode::Full, TruthMode::Observable}) {
    const std::string line = truth == TruthMode::Full
                                 ? "truth: full (every truth voxel of the region counts)"
                                 : "truth: observable (only truth voxels observable from the scan origins count)";
    INFO(line);
    const std::vector<std::string> warnings{recordCoverage(dir, 0, partial, truth),
                                            recordCoverage(dir, 1, outside, truth),
                                            recordCoverage(dir, 2, seen, truth)};
    REQUIRE((warnings[0].find("only 7 % of the truth voxels") != std::string::npos) == (truth == TruthMode::Full));
    REQUIRE(warnings[1].find("scans and truth are not aligned") != std::string::npos);
    REQUIRE(warnings[2].empty());
    const auto r = test::runIn(dir, "compare octomap-*.json knn-*.json --json c.json --csv c.csv --markdown c.md "
                                    "--latex c.tex --force");
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.output, Catch::Contains(line));  // what the tables are held to: the terminal says it
    CHECK_THAT(test::bytesOf(dir / "c.json"), Catch::Contains(nlohmann::json(warnings[1]).dump()));
    const std::string md = unescapedMarkdown(test::bytesOf(dir / "c.md")), tex = test::bytesOf(dir / "c.tex");
    CHECK_THAT(md, Catch::Contains("|\n\n- " + line + "\n"));  // under the per-set table
    const std::size_t warned = truth == TruthMode::Full ? 2 : 1;
    CHECK_THAT(tex, Catch::Contains("in percent; " + line + "; " + std::to_string(warned) +
                                    (warned == 1 ? " warning" : " warnings") +
                                    " of truth coverage or alignment listed after the table}"));
    for (int d = 0; d < 3; ++d) {
      const std::string dataset = "room-" + std::to_string(d);
      INFO(dataset);
      CHECK((md.find("- warning: " + dataset + ": " + warnings[d] + "\n") != std::string::npos) ==
            !warnings[d].empty());
      CHECK((tex.find("\\item warning: " + dataset + ": ") != std::string::npos) == !warnings[d].empty());
    }
    CHECK_THAT(tex, Catch::Contains("\\item warning: room-1: none of the 5000 points lies in the region: scans and "
                                    "truth are not aligned; likely causes: the truth or the poses shifted"));
    // The CSV: a truth and a coverage_warning column, read back whole by Python's csv module.
    const auto py = test::runShell("cd " + dir.string() + " && python3 -c \"import csv, json; print(json.dumps("
                                   "{r['dataset']: [r['truth'], r['coverage_warning']] for r in "
                                   "csv.DictReader(open('c.csv', newline=''))}))\"");
    INFO(py.output);
    REQUIRE(py.exit_code == 0);
    const nlohmann::json csv = nlohmann::json::parse(py.output);
    for (int d = 0; d < 3; ++d)
      CHECK(csv.at("room-" + std::to_string(d)) == nlohmann::json::array({truthModeName(truth), warnings[d]}));
    if (pdflatex) checkFitsPlainArticle(dir, "c.tex");
  }
}

TEST_CASE("compare --latex of five methods over 60 sets continues the per-set table in floats of at most 40 sets, "
          "each within the page") {
  // Old binary: one float of 60 sets, taller than the page ("Float too large"), its end lost.
  if (test::runShell("command -v pdflatex").exit_code != 0) {
    WARN("pdflatex not installed: the LaTeX over 60 sets is not compiled");
    return;
  }
  const auto dir = test::processScratch("compare-sixty");
  std::string files;
  for (int seed = 1; seed <= 60; ++seed) {
    const std::string ds = "ds" + std::to_string(seed);
    REQUIRE(test::runIn(dir, "scene --scans 2 --width 8 --height 6 --seed " + std::to_string(seed) + " --out " + ds)
                .exit_code == 0);
    std::string sweep = "sweep --dataset " + ds + " --quiet";
    for (const std::string grid : {"octomap-opt", "knn-opt", "sor-octomap-opt", "ror-octomap-opt", "range-octomap-opt"}) {
      sweep += " --grid " + grid + " --out " + ds + "-" + grid + ".json";
      files += " " + ds + "-" + grid + ".json";
    }
    REQUIRE(test::runIn(dir, sweep).exit_code == 0);
  }
  const auto r = test::runIn(dir, "compare" + files + " --latex t.tex");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string tex = test::bytesOf(dir / "t.tex");
  CHECK(tex.find("(sets 1-40 of 60)") != std::string::npos);
  CHECK(tex.find("(sets 41-60 of 60)") != std::string::npos);
  CHECK(tex.find("range OctoMap") != std::string::npos);  // five methods, by their display names
  checkFitsPlainArticle(dir, "t.tex");
}

TEST_CASE("compare's terminal output fits 100 columns with five methods and names every method's best map") {
  // Old binary: one line per set of about 380 characters (every method's AUC, best map and file side by side, then
  // 15 statistics columns).
  const auto dir = test::processScratch("compare-terminal");
  REQUIRE(test::runIn(dir, "scene --out ds").exit_code == 0);
  const std::vector<std::string> grids = {"octomap-opt", "knn-opt", "sor-octomap-opt", "ror-octomap-opt",
                                          "range-octomap-opt"};
  std::string files;
  for (const std::string& grid : grids) {
    REQUIRE(test::runIn(dir, "sweep --dataset ds --quiet --grid " + grid + " --out " + grid + ".json").exit_code == 0);
    files += " " + grid + ".json";
  }
  const auto r = test::runIn(dir, "compare" + files + " --json c.json --latex t.tex");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  // The LaTeX of five methods fits a plain article's text width too (old: the statistics table ran 1,154 pt past it).
  if (test::runShell("command -v pdflatex").exit_code == 0) {
    checkFitsPlainArticle(dir, "t.tex");
    CHECK(test::bytesOf(dir / "t.tex").find("range OctoMap") != std::string::npos);  // display names
  }
  std::istringstream lines(r.output);
  std::size_t widest = 0, count = 0;
  for (std::string line; std::getline(lines, line); ++count) widest = std::max(widest, line.size());
  CHECK(widest <= 100);
  CHECK(count > 20);
  const nlohmann::json rows = nlohmann::json::parse(test::bytesOf(dir / "c.json")).at("rows");
  for (const std::string& grid : grids) {
    const std::string method = grid.substr(0, grid.size() - 4);
    const nlohmann::json& best = rows.at(0).at("methods").at(method);
    // The method's line, then its parameters: what `map --from FILE --map-index N` rebuilds.
    CHECK(r.output.find("map " + best.at("map_index").dump() + " of " + grid + ".json") != std::string::npos);
    std::istringstream parameters(best.at("params").get<std::string>());  // each name=value, wrapped or not
    for (std::string parameter; parameters >> parameter;) CHECK(r.output.find(parameter) != std::string::npos);
  }
}

TEST_CASE("compare --csv and results export write numbers alike, and the exports of two files concatenate into one "
          "table by their method column") {
  // Old binary: compare wrote p_max as 0.97999999999999998 and export as 0.98; the export had no data-set or method
  // column, so rows of two files could not be told apart once concatenated.
  const auto dir = test::processScratch("csv-alike");
  const fs::path golden = occsweep::test::sourceTree() / "results" / "builtin";
  const std::string om = (golden / "octomap-opt.json").string(), knn = (golden / "knn-opt.json").string();
  REQUIRE(test::runIn(dir, "compare " + om + " " + knn + " --csv c.csv").exit_code == 0);
  REQUIRE(test::runIn(dir, "results export " + om + " --out o.csv").exit_code == 0);
  REQUIRE(test::runIn(dir, "results export " + knn + " --out k.csv").exit_code == 0);
  const char* check = R"(python3 -c "
import csv
c = list(csv.DictReader(open('c.csv')))
assert c[0]['knn.p_max'] == '0.98' and c[0]['octomap.p_max'] == '0.98', (c[0]['knn.p_max'], c[0]['octomap.p_max'])
rows = list(csv.DictReader(open('o.csv'))) + list(csv.DictReader(open('k.csv')))
assert {r['method'] for r in rows} == {'octomap', 'knn'}, 'methods'
assert {r['grid'] for r in rows} == {'octomap-opt', 'knn-opt'}, 'grids'
assert all(r['p_max'] == '0.98' for r in rows), 'p_max'
assert all(r['dataset'] == c[0]['dataset'] and r['truth'] == 'full' for r in rows), 'dataset'
def digits(s):  # the significant digits, whatever the notation (0.0001 and 1e-04 alike)
    return s.lower().split('e')[0].replace('-', '').replace('.', '').strip('0')
for r in rows:
    for key in ('p_t', 'tpr', 'fdr', 'auc_anchored'):
        if r[key]:  # the shortest text: as many digits as Python's shortest repr
            assert digits(r[key]) == digits(repr(float(r[key]))), (key, r[key])
print('alike', len(rows))
")";
  const auto py = test::runShell("cd " + dir.string() + " && " + check);
  INFO(py.output);
  CHECK(py.exit_code == 0);
  CHECK(py.output.find("alike 4230") != std::string::npos);  // 180 + 4,050 combinations
}

TEST_CASE("the export CSVs of three methods over three data sets concatenate into one table whose every number reads "
          "back equal to its results file's") {
  const auto dir = test::processScratch("csv-three-by-three");
  const std::vector<std::string> grids = {"octomap-opt", "knn-opt", "range-octomap-opt"};
  std::string exported;
  for (int seed = 1; seed <= 3; ++seed) {
    const std::string ds = "ds" + std::to_string(seed);
    REQUIRE(test::runIn(dir, "scene --scans 3 --width 16 --height 12 --seed " + std::to_string(seed) + " --out " + ds)
                .exit_code == 0);
    for (const std::string& grid : grids) {
      const std::string name = ds + "-" + grid;
      const std::string sweep = "sweep --dataset " + ds + " --grid " + grid + " --out " + name + ".json";
      REQUIRE(test::runIn(dir, sweep).exit_code == 0);
      REQUIRE(test::runIn(dir, "results export " + name + ".json --out " + name + ".csv").exit_code == 0);
      exported += " " + name;
    }
  }
  // Every CSV row against its results file: parameters, threshold, counts and rates, both AUCs, equal as doubles
  // (a text that reads back to another double, or a missing row, fails). An empty cell is JSON's null.
  const std::string check = R"(python3 - )" + exported + R"( 2>&1 <<'PY'
import csv, json, sys
rows, files = [], {}
for name in sys.argv[1:]:
    files[name] = json.load(open(name + '.json'))
    with open(name + '.csv', newline='') as f:
        rows += [dict(r, _file=name) for r in csv.DictReader(f)]
assert len({(r['dataset_hash'], r['method']) for r in rows}) == 9, 'data sets x methods'  # one scene's name, 3 seeds
def same(text, value):
    return (value is None and text == '') or (value is not None and float(text) == float(value))
checked = 0
for r in rows:
    res = files[r['_file']]
    m = res['maps'][int(r['map_index'])]
    assert m['map_index'] == int(r['map_index'])
    t = next(t for t in m['thresholds'] if t['id'] == int(r['id']))  # the combination's id in the grid
    assert r['dataset'] == res['dataset']['name'] and r['dataset_hash'] == res['dataset']['content_hash'], r['_file']
    assert r['method'] == res['grid']['method'], r['_file']
    for key, value in m['params'].items():
        assert same(r[key], value), (r['_file'], key, r[key], value)
    for key in ('p_t', 'tp', 'fp', 'fn', 'tn', 'tpr', 'fdr'):
        assert same(r[key], t[key]), (r['_file'], key, r[key], t[key])
    assert same(r['auc_anchored'], m['auc']['anchored']) and same(r['auc_observed'], m['auc']['observed'])
    checked += 1
expected = sum(len(m['thresholds']) for res in files.values() for m in res['maps'])
assert checked == expected, (checked, expected)
print('equal', checked)
PY)";
  const auto py = test::runShell("cd " + test::shellQuoted(dir.string()) + " && " + check);
  INFO(py.output);
  CHECK(py.exit_code == 0);
  CHECK(py.output.find("equal ") != std::string::npos);
}

TEST_CASE("compare prints within 100 columns when a results file's path is longer than a line") {
  // Old binary: the line naming the best map's file ran to the path's length (196 columns here).
  const auto dir = test::processScratch("compare-long-path");
  const fs::path golden = occsweep::test::sourceTree() / "results" / "builtin";
  const std::string folder = std::string(150, 'f');
  fs::create_directories(dir / folder);
  for (const char* file : {"octomap-opt.json", "knn-opt.json"}) fs::copy_file(golden / file, dir / folder / file);
  const auto r = test::runIn(dir, "compare " + folder + "/octomap-opt.json " + folder + "/knn-opt.json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::istringstream lines(r.output);
  std::string joined;
  for (std::string line; std::getline(lines, line);) {
    CHECK(line.size() <= 100);
    joined += line.substr(line.find_first_not_of(' ') == std::string::npos ? line.size() : line.find_first_not_of(' '));
  }
  CHECK(joined.find(folder + "/knn-opt.json") != std::string::npos);  // the whole path, cut at the lines' ends
}

TEST_CASE("two data sets with equal differences are too few to tell, not negligible (issue 44)") {
  // Two equal values gave the zero-width interval [+0.05, +0.05] and "negligible": no evidence at all.
  const fs::path dir = test::scratch("compare-two-equal");
  for (int d = 0; d < 2; ++d) writeGoldenDataset(dir, d, 0.05);
  const nlohmann::json knn = compareKnnStatistics(dir);
  const nlohmann::json& values = knn.at("optima_over_datasets").at("per_dataset");
  REQUIRE(values.size() == 2);
  CHECK(values[0].at("improvement_percent") == values[1].at("improvement_percent"));
  CHECK(values[0].at("improvement_percent").get<double>() == Approx(0.05).margin(2e-4));
  CHECK(knn.at("verdict") == "too few scenes to tell (n = 2; the smallest p possible is 0.5)");
  CHECK(knn.at("cross_validated_verdict").get<std::string>().find("negligible") == std::string::npos);
}

TEST_CASE("20 of 20 data sets better, exact p 1.9e-6, 95 % interval past 0.1 %: a gain, not negligible (issue 44)") {
  // 18 data sets +0.039 %, 2 +0.3 %: the old 90 % t interval lay within +-0.1 % and called it negligible beside a
  // printed 95 % interval reaching past the margin, while the exact test rejected "no difference".
  const fs::path dir = test::scratch("compare-twenty-better");
  for (int d = 0; d < 20; ++d) writeGoldenDataset(dir, d, d < 18 ? 0.039 : 0.3);
  const nlohmann::json knn = compareKnnStatistics(dir);
  const nlohmann::json& optima = knn.at("optima_over_datasets");
  CHECK(optima.at("test").at("p_value").get<double>() == Approx(2.0 / (1 << 20)));
  CHECK(optima.at("improvement_percent").at("upper").get<double>() > 0.1);
  CHECK(knn.at("verdict") == "gain");
}

TEST_CASE("grids that nest: the optima verdict is no gain but says why, the cross-validated one decides (issue 44)") {
  // k-NN's results hold OctoMap's best map on every set, so its difference is >= 0 by construction and the exact
  // test's "no difference" is false by design: old "gain".
  const fs::path dir = test::scratch("compare-nested");
  for (int d = 0; d < 8; ++d) writeGoldenDataset(dir, d, 0.3 + 0.07 * d, Nested::InItsFile);
  const nlohmann::json knn = compareKnnStatistics(dir);
  CHECK(knn.at("sets_holding_baseline_best") == 8);
  CHECK(knn.at("optima_over_datasets").at("test").at("p_value").get<double>() == Approx(2.0 / 256));
  CHECK(knn.at("verdict") ==
        "at least the baseline by construction (holds octomap's best on all sets of 8 of 8 scenes): not a test of "
        "the method");
  CHECK(knn.at("cross_validated_verdict").get<std::string>().find("by construction") == std::string::npos);
  // The table's test column beside that verdict: over the scenes that do not nest (none here), not the nested
  // scenes' p = 2/256 (old: "0.00781 (Holm 0.00781)" beside "not a test of the method").
  REQUIRE(test::runIn(dir, "compare knn-*.json octomap-*.json --markdown c.md").exit_code == 0);
  const std::string md = test::bytesOf(dir / "c.md");
  const std::size_t row = md.find("| k-NN |");
  REQUIRE(row != std::string::npos);
  const std::string knn_row = md.substr(row, md.find('\n', row) - row);
  INFO(knn_row);
  CHECK(knn_row.find("0.0078") == std::string::npos);  // 2/256 = 0.0078125, printed to 2 or 3 digits
}

// Each set of `files` (syntheticComparison's base/other pairs) for which `holds(set)` also gets, in "other"'s
// results, a copy of "base"'s best map: there "other" holds the baseline's best exactly.
template <typename Holds>
void holdBaselineBest(std::vector<ResultsFile>& files, Holds holds) {
  for (std::size_t i = 0; i + 1 < files.size(); i += 2) {
    if (!holds(i / 2)) continue;
    const auto lower = [](const MapResult& a, const MapResult& b) { return a.area.anchored < b.area.anchored; };
    MapResult copy = *std::max_element(files[i].maps.begin(), files[i].maps.end(), lower);
    copy.map_index = files[i + 1].maps.size();
    files[i + 1].maps.push_back(copy);
  }
}

TEST_CASE("grids that nest are counted in units: the optima verdict is decided on the units that do not nest") {
  // "other" better by 0.05 on every map, three sets per data set (the unit here); some sets also hold the
  // baseline's best. The old rule counted sets, "by construction" past half of them.
  SECTION("two of every data set's three sets hold it (16 of 24 sets): no unit nests, a gain (old: by construction)") {
    auto files = syntheticComparison(7, 15, 15, 0.05, true, 8);
    holdBaselineBest(files, [](std::size_t set) { return set % 3 != 2; });
    const MethodStatistics s = statisticsFor(files, "other");
    CHECK(s.sets_holding_baseline_best == 16);
    CHECK(s.scenes_holding_baseline_best == 0);
    CHECK(s.optima.verdict.text == "gain");
  }
  SECTION("every set of 4 of 8 data sets (12 of 24 sets): the other 4 are too few to tell (old: gain)") {
    auto files = syntheticComparison(7, 15, 15, 0.05, true, 8);
    holdBaselineBest(files, [](std::size_t set) { return set < 12; });
    const MethodStatistics s = statisticsFor(files, "other");
    CHECK(s.sets_holding_baseline_best == 12);
    CHECK(s.scenes_holding_baseline_best == 4);
    CHECK(s.optima.verdict.text == "at least the baseline by construction (holds base's best on all sets of 4 of 8 "
                                   "data sets; the other 4 are too few to tell): not a test of the method");
  }
  SECTION("every set of 2 of 10 data sets: the verdict over the other 8, which say so (old: over all 10)") {
    auto files = syntheticComparison(7, 15, 15, 0.05, true, 10);
    holdBaselineBest(files, [](std::size_t set) { return set < 6; });
    const MethodStatistics s = statisticsFor(files, "other");
    CHECK(s.scenes_holding_baseline_best == 2);
    CHECK(s.optima.verdict.text == "gain over the 8 data sets where the grids do not nest, 2 of 10 holding base's "
                                   "best on all their sets");
    CHECK(s.optima.verdict.basis.find("n = 8 data sets") == 0);
    // The sample after the verdict's n names both counts (old: "n = 8 data sets; ...; 10 data sets (...)").
    CHECK(s.optima.verdict.basis.find("; 8 data sets where the grids do not nest, of 10 data sets (") !=
          std::string::npos);
    REQUIRE(s.optima.test);
    CHECK(s.optima.test->nonzero == 10);  // the description stays over every unit
  }
  SECTION("every set of 4 of 4 data sets: too few to tell over all of them, said first") {
    auto files = syntheticComparison(7, 15, 15, 0.05, true, 4);
    holdBaselineBest(files, [](std::size_t) { return true; });
    const MethodStatistics s = statisticsFor(files, "other");
    CHECK(s.scenes_holding_baseline_best == 4);
    CHECK(s.optima.verdict.text == "too few data sets to tell (n = 4; the smallest p possible is 0.125)");
  }
}

TEST_CASE("grids that nest: the baseline's best in a second results file of the method counts (issue 44)") {
  // Two k-NN files per data set (compare --allow-mixed), OctoMap's best map only in the second; k-NN's best is taken
  // from the first. The old binary looked only in the best's file: 0 sets hold it, and the optima verdict was "gain".
  const fs::path dir = test::scratch("compare-nested-second-file");
  for (int d = 0; d < 8; ++d) writeGoldenDataset(dir, d, 0.3 + 0.07 * d, Nested::InASecondFile);
  const nlohmann::json knn = compareKnnStatistics(dir, " --allow-mixed");
  CHECK(knn.at("sets_holding_baseline_best") == 8);
  CHECK(knn.at("verdict") ==
        "at least the baseline by construction (holds octomap's best on all sets of 8 of 8 scenes): not a test of "
        "the method");
  CHECK(knn.value("scenes_holding_baseline_best", -1) == 8);
}

TEST_CASE("every output of compare says which verdicts Holm's correction ran over together (issue 44)") {
  // The old binary corrected the optima and the cross-validated verdicts as two families without saying so
  // anywhere: a reader could not tell what alpha 0.05 held over.
  const fs::path dir = test::scratch("compare-families");
  for (int d = 0; d < 3; ++d) writeGoldenDataset(dir, d, 0.05 + 0.1 * d);
  const test::CommandResult r =
      test::runIn(dir, "compare *.json --json c.json --markdown c.md --latex c.tex");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string families = "Holm families, each corrected by itself: the optima verdict of knn against octomap "
                               "alone (no correction); the cross-validated verdict of knn against octomap alone (no "
                               "correction)";
  auto oneSpaced = [](const std::string& text) {  // compare wraps its terminal lines at 100 columns
    std::string out;
    for (char c : text)
      if (!std::isspace(static_cast<unsigned char>(c))) out += c;
      else if (!out.empty() && out.back() != ' ') out += ' ';
    return out;
  };
  CHECK_THAT(oneSpaced(r.output), Catch::Contains(families));
  // The tables name the methods by their display names.
  const std::string displayed = "Holm families, each corrected by itself: the optima verdict of k-NN against "
                                "OctoMap alone (no correction); the cross-validated verdict of k-NN against OctoMap "
                                "alone (no correction)\n";
  CHECK_THAT(test::bytesOf(dir / "c.md"), Catch::Contains("- " + displayed));
  CHECK_THAT(test::bytesOf(dir / "c.tex"), Catch::Contains("\\item " + displayed));
  const nlohmann::json out = nlohmann::json::parse(test::bytesOf(dir / "c.json"));
  for (const nlohmann::json& m : out.at("statistics"))
    if (m.at("method") == "knn") {
      CHECK(m.at("optima_over_datasets").at("holm_family") ==
            "the optima verdict of knn against octomap alone (no correction)");
      CHECK(m.at("cross_validated_over_datasets").at("holm_family") ==
            "the cross-validated verdict of knn against octomap alone (no correction)");
    }
}

TEST_CASE("compare's tables name the scene as the unit where provenance groups data sets into scenes (issue 44)") {
  // Three rooms' results, the first two replicates of one scene (one recorded scene): 3 data sets over 2 scenes.
  // The old binary headed the columns of the verdicts' values "over data sets", "exact test over data sets" and
  // "leave-one-data-set-out" while their values were over the 2 scenes.
  const fs::path dir = test::scratch("compare-scene-headers");
  for (int d = 0; d < 3; ++d) writeGoldenDataset(dir, d, 0.05 + 0.1 * d);
  for (const char* method : {"octomap", "knn"}) {
    const fs::path replicate = dir / (std::string(method) + "-1.json");
    ResultsFile f = readResults(replicate);
    f.header.point_cloud_set["provenance"] =
        readResults(dir / (std::string(method) + "-0.json")).header.point_cloud_set.at("provenance");
    writeResults(f, replicate);
  }
  const nlohmann::json knn = compareKnnStatistics(dir);
  REQUIRE(knn.at("datasets") == 3);
  REQUIRE(knn.at("scenes") == 2);
  const test::CommandResult r = test::runIn(dir, "compare octomap-*.json knn-*.json --markdown c.md --latex c.tex");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string md = test::bytesOf(dir / "c.md"), tex = test::bytesOf(dir / "c.tex");
  for (const auto& [output, text] : {std::pair{"terminal", r.output}, {"markdown", md}, {"latex", tex}}) {
    INFO(output);
    CHECK_THAT(text, Catch::Contains("sets (data sets over scenes)"));
    CHECK_THAT(text, Catch::Contains("exact test over scenes: p (Holm)"));
    CHECK_THAT(text, Catch::Contains("leave-one-scene-out (gap)"));
    CHECK_THAT(text, Catch::Contains(" (by scene)"));  // "improvement % (by scene)", '%' escaped in LaTeX
    CHECK_THAT(text, !Catch::Contains("over data sets") && !Catch::Contains("by data set") &&
                         !Catch::Contains("leave-one-data-set-out"));
  }
  CHECK_THAT(md, Catch::Contains("| 3 (3 over 2 scenes) |"));
}
