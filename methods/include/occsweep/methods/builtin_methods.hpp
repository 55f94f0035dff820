// The methods occsweep ships (docs/methods.md cites each), one folder each under methods/: OctoMap, the k-NN inverse
// sensor model, the two PCL outlier filters before OctoMap, and OctoMap with a hit probability that falls with the
// stereo depth error. Core's registry knows none of them: a program registers them (the command does it first).
#pragma once

namespace occsweep {

/// Registers every built-in method (octomap, knn, sor-octomap, ror-octomap, range-octomap) once; later calls do
/// nothing. Throws std::invalid_argument when a program registered a method of one of their names first.
void registerBuiltinMethods();

}  // namespace occsweep
