// `pyramid`: inspect, check, extract and verify pyramid files, and build them.
#include "cli/programs.hpp"

int main(int argc, char** argv) { return pyramid::cli::pyramidProgram(argc, argv); }
