// The files a mosaic reads, from the inputs a command line names (doc/input.md, "Many inputs"):
// files, directories of TIFFs, glob patterns, GDAL VRTs of plain sources, and a list file.
// Only names are handled here; the files are opened, and their grid checked, by
// RasterSource::openMosaic.
#pragma once
#include <string>
#include <vector>

namespace pyramid {

// What a mosaic's inputs are, as named on a command line.
struct InputList {
    std::vector<std::string> paths;      // the files, in priority order (first listed first), no duplicates
    std::vector<std::string> vrtSources; // for each VRT argument: its path (for reports); empty if none
};

// Each argument is one of:
//  * a file (any raster; a path ending in .vrt, case-insensitive, is a GDAL VRT, below);
//  * a directory: its *.tif / *.tiff files (case-insensitive), sorted by name, not recursive; an
//    empty one is an error;
//  * a glob pattern (an argument containing *, ? or [ that does not exist as a file): expanded
//    with glob(3), sorted; no match is an error;
//  * `listFile` (when not empty) adds its lines after the arguments: one path per line, blank
//    lines and lines starting with # skipped, surrounding whitespace trimmed, relative paths
//    resolved against the list file's directory; each line may itself be a directory, glob or
//    VRT as above.
// A GDAL VRT contributes the files of its sources in order of first appearance: the text of
// every <SourceFilename> inside <SimpleSource> or <ComplexSource> of every <VRTRasterBand>,
// resolved against the VRT's directory when relativeToVRT="1" (else taken as is). Refused,
// naming the VRT: a root element other than VRTDataset; a VRTRasterBand with a subClass
// attribute (derived/warped bands); a source element of any other kind (KernelFilteredSource,
// AveragedSource...); a ComplexSource with ScaleRatio other than 1 or ScaleOffset other than 0
// or a LUT; a SourceFilename that is not a plain file (e.g. starts with /vsi or contains "://");
// no source at all; malformed XML.
// Every resulting path must exist as a regular file, else Error(path, "no such file") naming
// also where it came from (e.g. "tiles.vrt: tile_3.tif: no such file"). Duplicates (same path
// after lexical normalisation) are kept once, at their first place. Throws Error for an empty
// result.
//
// Beyond the rules above, precisely:
//  * Names are sorted by byte value (directories and glob matches alike), so the order does not
//    depend on the locale. A directory's entries whose names start with '.' are skipped, as a
//    glob's '*' skips them (so macOS's "._x.tif" companions are never read); its
//    subdirectories are skipped, and any other matching entry must be a regular file.
//  * A glob match is taken as if given as an argument itself: a directory match contributes its
//    TIFFs, a .vrt match its sources. A list file's relative glob is matched in the list file's
//    directory, whatever characters that directory's name holds.
//  * A VRT source that is itself a .vrt contributes its own sources, by the same rules (a VRT
//    that is, through others, its own source is refused). `vrtSources` holds, once each, the
//    VRTs named by the arguments, the list file's lines or their glob matches, in order.
//  * A VRT band's <Scale>, <Offset> and <UnitType> (which gdalbuildvrt copies from its sources)
//    must be what each of its source files declares itself (GDAL's band metadata, the heights'
//    unit), since each file's heights are read by its own: a VRT that declares others is refused.
//  * A VRT is also refused for a root subClass (VRTWarpedDataset...), a <MaskBand>, a
//    ComplexSource with <Exponent> or <ColorTableComponent> (values not the files' own), a
//    source with no, an empty or more than one <SourceFilename>, and relativeToVRT other than 0
//    or 1. Element and attribute names are compared ignoring case, as GDAL does; a
//    <SourceFilename>'s surrounding whitespace is trimmed.
//  * Duplicates are found by the path made absolute against the working directory and then
//    normalised lexically ("a/./b", "a/../b", "b" and "$PWD/b" are one file; symlinks are not
//    followed). The path kept is spelled as it was named (joined to the list file's or the
//    VRT's directory when resolved against it).
//  * Where a path came from is named before it: "LIST:LINE" for a list file's line, then each
//    VRT it was found through ("inputs.txt:3: tiles.vrt: tile_3.tif: no such file").
InputList expandInputs(const std::vector<std::string>& arguments, const std::string& listFile = "");

} // namespace pyramid
