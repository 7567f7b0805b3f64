// `preprocessSphericalOrtho`: the `pyramid sphere-ortho` command as a program of its own.
#include "cli/programs.hpp"

int main(int argc, char** argv) { return pyramid::cli::preprocessSphericalOrthoProgram(argc, argv); }
