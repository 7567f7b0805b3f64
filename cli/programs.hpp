// The seven programs: each main_PROGRAM.cpp calls its function here. The parsers are built in
// cli/programs.cpp, with the commands, so that the programs' own files need no CLI11 (its
// header takes seconds to compile in every file that includes it).
#pragma once

namespace pyramid::cli {

int pyramidProgram(int argc, char** argv);
int preprocessDemProgram(int argc, char** argv);
int preprocessOrthoProgram(int argc, char** argv);
int preprocessSphericalDemProgram(int argc, char** argv);
int preprocessSphericalOrthoProgram(int argc, char** argv);
int preprocessApertureProgram(int argc, char** argv);
int preprocessSphericalApertureProgram(int argc, char** argv);

} // namespace pyramid::cli
