// The commands of the `pyramid` program. Each setup function declares its options on the
// (sub)command it is given and returns the function that runs it once the command line is
// parsed. preprocessDem and preprocessOrtho are the `dem` and `ortho` commands on their own.
#pragma once
#include <functional>

namespace CLI {
class App;
}

namespace pyramid::cli {

using CommandRunner = std::function<int()>;

CommandRunner setupInfoCommand(CLI::App& app);    // pyramid info FILE [--json]
CommandRunner setupTileCommand(CLI::App& app);    // pyramid tile FILE LEVEL TX TY -o OUT
CommandRunner setupCheckCommand(CLI::App& app);   // pyramid check FILE [--json]
CommandRunner setupDemCommand(CLI::App& app);     // pyramid dem / preprocessDem
CommandRunner setupOrthoCommand(CLI::App& app);   // pyramid ortho / preprocessOrtho
CommandRunner setupSphereDemCommand(CLI::App& app);   // pyramid sphere-dem / preprocessSphericalDem
CommandRunner setupSphereOrthoCommand(CLI::App& app); // pyramid sphere-ortho / preprocessSphericalOrtho
CommandRunner setupVerifyCommand(CLI::App& app);  // pyramid verify FILE --source INPUT [--gl]
CommandRunner setupMergeCommand(CLI::App& app);   // pyramid merge PART... [-o DIR]
CommandRunner setupHeightCommand(CLI::App& app);  // pyramid height FILE|DIR --grid/--pixel/--lonlat
CommandRunner setupPreviewCommand(CLI::App& app); // pyramid preview FILE|SET -o OUT.png
CommandRunner setupRecodeCommand(CLI::App& app);  // pyramid recode FILE -o OUT --compression C
CommandRunner setupApertureCommand(CLI::App& app); // pyramid aperture / preprocessAperture
CommandRunner setupSphereApertureCommand(CLI::App& app); // pyramid sphere-aperture / preprocessSphericalAperture
CommandRunner setupServeCommand(CLI::App& app);  // pyramid serve PATH [--port N] [--bind ADDRESS]

} // namespace pyramid::cli
