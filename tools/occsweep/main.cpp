// occsweep: OctoMap against the k-NN inverse sensor model, voxel for voxel, over parameter grids.
#include "command_line.hpp"

int main(int argc, char** argv) { return occsweep::cli::runCommandLine(argc, argv); }
