// `preprocessSphericalDem`: the `pyramid sphere-dem` command as a program of its own.
#include "cli/programs.hpp"

int main(int argc, char** argv) { return pyramid::cli::preprocessSphericalDemProgram(argc, argv); }
