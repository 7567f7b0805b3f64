// The preprocessors as a library (doc/library.md): the four encoders and their verification,
// from files or from a caller's own sources (sources.hpp). This header and sources.hpp are the
// C++ API of libpyramid::preprocess; the programs preprocessDem, preprocessOrtho,
// preprocessSphericalDem and preprocessSphericalOrtho use nothing else of the library.
//
// Every call checks its options first (OptionError names the field), writes its outputs
// atomically (all of them or none) and throws Error with a one-line message on bad input;
// options.progress sees (tiles done, total) and options.cancelled may stop a run (Cancelled).
#pragma once
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/api/sources.hpp"
#include "libpyramid/distribute/split_build.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/encode/residual/residual_recode.hpp"
#include "libpyramid/input/input_list.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "libpyramid/verify/ortho_verify.hpp"

namespace pyramid {

// preprocessDem: a residual pyramid file of the heights. A caller's source is not georeferenced
// (options.target does not apply, and no sidecar is written).
DemReport encodeDem(const ElevationSource& source, const std::string& output, const DemEncodeOptions& options);

// preprocessOrtho: the ortho pyramids of the colours, into `directory`.
OrthoReport encodeOrtho(const ColourSource& source, const std::string& directory, const OrthoEncodeOptions& options);

// preprocessSphericalDem: six (or options.faces) cube-face residual pyramids of the planet's
// heights (planet.channels() must be 1), times options.heightScale. options.extent, dem.band
// and dem.nodata do not apply.
SphericalDemReport encodeSphericalDem(const PlanetSource& planet, const std::string& directory,
                                      const SphericalDemOptions& options);

// preprocessSphericalOrtho: the cube-face ortho pyramids of the planet's colours (values 0 to
// 255). options.extent does not apply.
SphericalOrthoReport encodeSphericalOrtho(const PlanetSource& planet, const std::string& directory,
                                          const SphericalOrthoOptions& options);

// `pyramid verify FILE --source`, against a caller's heights: every level rebuilt by the CPU
// producer and compared with the source sampled as the encoder sampled it.
DemVerifyReport verifyDem(const std::string& file, const ElevationSource& source, const DemVerifyOptions& options);

// The faces encodeSphericalDem(planet, directory, ...) wrote, against the planet: one report
// per face.
std::vector<DemVerifyReport> verifySphericalDem(const std::string& directory, const PlanetSource& planet,
                                                const SphericalDemVerifyOptions& options);

} // namespace pyramid
