// occsweep with one more method: examples/occupancy_method's density-octomap, registered from outside the library
// before the command line runs, as a program with a method of its own does (docs/methods.md, "Bring your own
// method"). test_map_methods maps and sweeps it through every command. With OCCSWEEP_EXAMPLE_PARAMETER=NAME it also
// registers density-octomap-extra, the same method with one more parameter of that name: how test_map_methods sees
// the command refuse a parameter named like one of map's flags.
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>

#include "command_line.hpp"
#include "example_method.hpp"
#include "occsweep/core/method_registry.hpp"

namespace {

class ExtraParameterMethod final : public occsweep::MappingMethod {
 public:
  explicit ExtraParameterMethod(std::string extra) : extra_(std::move(extra)) {}
  std::string name() const override { return "density-octomap-extra"; }
  std::string description() const override { return base_.description(); }
  std::string reference() const override { return base_.reference(); }
  std::vector<occsweep::MethodParameter> parameters() const override {
    std::vector<occsweep::MethodParameter> p = base_.parameters();
    p.push_back({extra_, extra_, "named as the test says", 1, 0, 2, false, false, false, "test"});
    return p;
  }
  std::vector<occsweep::ParameterRelation> relations() const override { return base_.relations(); }
  occsweep::MapRule rule(const occsweep::MethodValues& v, const occsweep::RuleContext& c) const override {
    return base_.rule({v.begin(), v.end() - 1}, c);
  }

 private:
  DensityOctoMapMethod base_;
  std::string extra_;
};

}  // namespace

int main(int argc, char** argv) {
  occsweep::registerMethod(std::make_shared<DensityOctoMapMethod>());
  if (const char* extra = std::getenv("OCCSWEEP_EXAMPLE_PARAMETER"))
    occsweep::registerMethod(std::make_shared<ExtraParameterMethod>(extra));
  return occsweep::cli::runCommandLine(argc, argv);
}
