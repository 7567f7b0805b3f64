// The files a mosaic reads, from a command line's inputs (expandInputs): order and duplicates,
// directories (sorted, TIFFs only), glob patterns, a list file (comments, relative lines, its
// own directory's name escaped), GDAL VRTs (relative and absolute sources over two bands,
// entities, nested VRTs), and every refusal, each naming the argument or VRT and the reason.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/input_list.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using Paths = std::vector<std::string>;

// Writes TEXT to PATH, creating its directories.
void write(const std::string& path, const std::string& text) {
    fs::create_directories(fs::path(path).parent_path());
    std::ofstream out(path, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good()) << path;
}

// An (unreadable as a raster, but regular) file at each path.
void touch(const std::vector<std::string>& paths) {
    for (const std::string& path : paths) {
        write(path, "not a raster");
    }
}

std::string errorOf(const Paths& arguments, const std::string& listFile = "") {
    try {
        expandInputs(arguments, listFile);
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

// A VRT of one band with the given sources' XML.
std::string vrtOfBand(const std::string& sources) {
    return "<VRTDataset rasterXSize=\"10\" rasterYSize=\"10\">\n"
           "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n" +
           sources + "\n  </VRTRasterBand>\n</VRTDataset>\n";
}

// The working directory changed for a scope.
class WorkingDirectory {
public:
    explicit WorkingDirectory(const std::string& path) : previous_(fs::current_path()) { fs::current_path(path); }
    ~WorkingDirectory() { fs::current_path(previous_); }
    WorkingDirectory(const WorkingDirectory&) = delete;
    WorkingDirectory& operator=(const WorkingDirectory&) = delete;

private:
    fs::path previous_;
};

TEST(InputList, ArgumentsKeepTheirOrderAndDuplicatesTheirFirstPlace) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/a.tif", d + "/b.tif", d + "/c.png", d + "/sub/keep"});
    const InputList list =
        expandInputs({d + "/b.tif", d + "/a.tif", d + "/./b.tif", d + "/sub/../a.tif", d + "/c.png", d + "//b.tif"});
    EXPECT_EQ(list.paths, (Paths{d + "/b.tif", d + "/a.tif", d + "/c.png"}));
    EXPECT_TRUE(list.vrtSources.empty());

    // Relative and absolute spellings of one file are one file; the first spelling is kept.
    WorkingDirectory cwd(d);
    EXPECT_EQ(expandInputs({"a.tif", d + "/a.tif", "./a.tif", "sub/../b.tif", "b.tif"}).paths,
              (Paths{"a.tif", "sub/../b.tif"}));
}

TEST(InputList, MissingOrIrregularFilesAndEmptyInputsAreRefused) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/a.tif"});
    EXPECT_EQ(errorOf({d + "/a.tif", d + "/nope.tif"}), d + "/nope.tif: no such file");
    ASSERT_EQ(::mkfifo((d + "/pipe.tif").c_str(), 0600), 0);
    EXPECT_EQ(errorOf({d + "/pipe.tif"}), d + "/pipe.tif: not a regular file");
    // In a directory, too.
    EXPECT_EQ(errorOf({d}), d + "/pipe.tif: not a regular file");
    EXPECT_EQ(errorOf({""}), "an empty argument names no file");
    EXPECT_EQ(errorOf({}), "no input file given");
}

TEST(InputList, DirectoryGivesItsTiffsAndHeightFilesSortedByName) {
    test::TempDir dir;
    const std::string t = dir.file("tiles");
    touch({t + "/b.tif", t + "/A.TIFF", t + "/c.Tif", t + "/a.tif", t + "/notes.txt", t + "/x.png", t + "/tif",
           t + "/a.tif.aux.xml", t + "/.hidden.tif", t + "/._b.tif", t + "/sub.tif/inner.tif", t + "/deeper/z.tif",
           t + "/N46W122.hgt", t + "/N46W122.hgt.aux.xml", t + "/n46.dt2", t + "/N47.DT1", t + "/n48.dt3",
           t + "/ned.img", t + "/ned.img.aux.xml", t + "/ned.rrd", t + "/ned.ige", t + "/dgm1.xyz", t + "/dgm1.prj", t + "/quad.DEM", t + "/quad.dem.aux.xml"});
    // Byte order: capitals first, whatever the locale.
    const Paths expected{t + "/A.TIFF", t + "/N46W122.hgt", t + "/N47.DT1", t + "/a.tif",    t + "/b.tif",
                         t + "/c.Tif",  t + "/dgm1.xyz",    t + "/n46.dt2", t + "/ned.img", t + "/quad.DEM"};
    EXPECT_EQ(expandInputs({t}).paths, expected);
    EXPECT_EQ(expandInputs({t + "/"}).paths, expected);
    // A file named before the directory keeps its place; the directory does not repeat it.
    EXPECT_EQ(expandInputs({t + "/b.tif", t}).paths,
              (Paths{t + "/b.tif", t + "/A.TIFF", t + "/N46W122.hgt", t + "/N47.DT1", t + "/a.tif", t + "/c.Tif",
                     t + "/dgm1.xyz", t + "/n46.dt2", t + "/ned.img", t + "/quad.DEM"}));
}

TEST(InputList, DirectoryWithoutTiffsIsRefused) {
    test::TempDir dir;
    const std::string empty = dir.file("empty");
    const std::string others = dir.file("others");
    fs::create_directories(empty);
    touch({others + "/x.png", others + "/x.hdr", others + "/.y.tif", others + "/sub/z.tif", others + "/sub/z.asc"});
    EXPECT_EQ(errorOf({empty}), empty + ": the directory holds no .tif, .tiff, .hgt, .dt0-2, .img, .xyz, .dem, .asc, .bil or .flt file");
    EXPECT_EQ(errorOf({others}), others + ": the directory holds no .tif, .tiff, .hgt, .dt0-2, .img, .xyz, .dem, .asc, .bil or .flt file");
}

TEST(InputList, GlobPatternsAreExpandedSorted) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/t1.tif", d + "/t2.tif", d + "/t10.tif", d + "/u1.tif", d + "/t3.png", d + "/x1.tif", d + "/x[1].tif"});
    EXPECT_EQ(expandInputs({d + "/t*.tif"}).paths, (Paths{d + "/t1.tif", d + "/t10.tif", d + "/t2.tif"}));
    EXPECT_EQ(expandInputs({d + "/t?.tif"}).paths, (Paths{d + "/t1.tif", d + "/t2.tif"}));
    EXPECT_EQ(expandInputs({d + "/[tu]1.tif", d + "/t*"}).paths,
              (Paths{d + "/t1.tif", d + "/u1.tif", d + "/t10.tif", d + "/t2.tif", d + "/t3.png"}));
    // A file whose name holds glob characters is that file, not a pattern.
    EXPECT_EQ(expandInputs({d + "/x[1].tif"}).paths, (Paths{d + "/x[1].tif"}));
    EXPECT_EQ(errorOf({d + "/z*.tif"}), d + "/z*.tif: no file matches the pattern");
    EXPECT_EQ(errorOf({d + "/nowhere/*.tif"}), d + "/nowhere/*.tif: no file matches the pattern");
}

TEST(InputList, GlobMatchesAreTakenAsArguments) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/m_dir/b.tif", d + "/m_dir/a.tif", d + "/m_dir/skip.png", d + "/m_file.tif", d + "/src/v.tif"});
    write(d + "/m.vrt", vrtOfBand("<SimpleSource><SourceFilename relativeToVRT=\"1\">src/v.tif</SourceFilename>"
                                  "</SimpleSource>"));
    const InputList list = expandInputs({d + "/m*"});
    // Matches in byte order: "m.vrt" < "m_dir" < "m_file.tif".
    EXPECT_EQ(list.paths, (Paths{d + "/src/v.tif", d + "/m_dir/a.tif", d + "/m_dir/b.tif", d + "/m_file.tif"}));
    EXPECT_EQ(list.vrtSources, (Paths{d + "/m.vrt"}));
}

TEST(InputList, ListFileAddsItsLinesAfterTheArguments) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/tiles/a.tif", d + "/tiles/b.tif", d + "/tiles/c.tif", d + "/more/y.tif", d + "/more/x.tif",
           d + "/abs.tif"});
    const std::string listFile = d + "/lists/inputs.txt";
    write(listFile, "# the tiles of the test\n"
                    "\n"
                    "   \t\n"
                    "   ../tiles/b.tif  \t\r\n"
                    "../tiles/a.tif\r\n"
                    "#../tiles/c.tif\n"
                    "  # an indented comment\n" +
                        d +
                        "/abs.tif\n"
                        "../more\n"
                        "../tiles/[bc].tif"); // no final newline
    const InputList list = expandInputs({d + "/tiles/a.tif"}, listFile);
    const std::string l = d + "/lists/";
    EXPECT_EQ(list.paths, (Paths{d + "/tiles/a.tif", l + "../tiles/b.tif", d + "/abs.tif", l + "../more/x.tif",
                                 l + "../more/y.tif", l + "../tiles/c.tif"}));
    EXPECT_TRUE(list.vrtSources.empty());

    // Relative to the list file, not to the working directory.
    WorkingDirectory cwd(d + "/more");
    EXPECT_EQ(expandInputs({}, "../lists/inputs.txt").paths.front(), "../lists/../tiles/b.tif");
}

TEST(InputList, ListFileGlobsMatchInItsOwnDirectoryWhateverItsName) {
    test::TempDir dir;
    const std::string d = dir.path();
    // Unescaped, "d[1]/*.tif" would match d1/zz.tif instead.
    touch({d + "/d[1]/q.tif", d + "/d[1]/p.tif", d + "/d1/zz.tif"});
    write(d + "/d[1]/list.txt", "*.tif\n");
    EXPECT_EQ(expandInputs({}, d + "/d[1]/list.txt").paths, (Paths{d + "/d[1]/p.tif", d + "/d[1]/q.tif"}));
}

TEST(InputList, ListFileErrorsNameTheLine) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/a.tif"});
    write(d + "/list.txt", "# one good, one missing\na.tif\nmissing.tif\n");
    EXPECT_EQ(errorOf({}, d + "/list.txt"), d + "/list.txt:3: " + d + "/missing.tif: no such file");
    write(d + "/glob.txt", "\n\n*.png\n");
    EXPECT_EQ(errorOf({}, d + "/glob.txt"), d + "/glob.txt:3: " + d + "/*.png: no file matches the pattern");
    EXPECT_EQ(errorOf({d + "/a.tif"}, d + "/nolist.txt"), d + "/nolist.txt: no such file");
    write(d + "/comments.txt", "# nothing\n\n");
    EXPECT_EQ(expandInputs({d + "/a.tif"}, d + "/comments.txt").paths, (Paths{d + "/a.tif"}));
    EXPECT_EQ(errorOf({}, d + "/comments.txt"), d + "/comments.txt: lists no file, and no other input is given");
}

TEST(InputList, VrtGivesItsSourcesOnceInOrderOfFirstAppearance) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/tiles/a.tif", d + "/tiles/b.tif", d + "/tiles/c.tif", d + "/elsewhere/d.tif"});
    const std::string vrt = d + "/mosaic.vrt";
    write(vrt,
          "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
          "<!-- written by hand: <SourceFilename>ignored.tif</SourceFilename> -->\n"
          "<VRTDataset rasterXSize=\"512\" rasterYSize='256'>\n"
          "  <SRS dataAxisToSRSAxisMapping=\"2,1\">GEOGCS[&quot;WGS 84&quot;]</SRS>\n"
          "  <GeoTransform> 10, 0.1, 0, 50, 0, -0.1</GeoTransform>\n"
          "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
          "    <NoDataValue>-32768</NoDataValue>\n"
          "    <SimpleSource>\n"
          "      <SourceFilename relativeToVRT=\"1\">tiles/b.tif</SourceFilename>\n"
          "      <SourceBand>1</SourceBand>\n"
          "      <SourceProperties RasterXSize=\"256\" RasterYSize=\"256\" DataType=\"Float32\"/>\n"
          "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"256\" ySize=\"256\" />\n"
          "      <DstRect xOff=\"256\" yOff=\"0\" xSize=\"128\" ySize=\"128\" />\n"
          "    </SimpleSource>\n"
          "    <ComplexSource>\n"
          "      <SourceFilename\n relativeToVRT = '1' shared=\"0\" >\n  tiles/a.tif\n  </SourceFilename >\n"
          "      <ScaleRatio>1.0</ScaleRatio><ScaleOffset> 0 </ScaleOffset>\n"
          "      <NODATA>-32768</NODATA>\n"
          "    </ComplexSource>\n"
          "    <SimpleSource><!-- an absolute path -->"
          "<SourceFilename relativeToVRT=\"0\">" +
              d +
              "/elsewhere/d.tif</SourceFilename></SimpleSource>\n"
              "  </VRTRasterBand>\n"
              "  <VRTRasterBand dataType=\"Float32\" band=\"2\">\n"
              "    <SimpleSource><SourceFilename relativeToVRT=\"1\">tiles/a.tif</SourceFilename></SimpleSource>\n"
              "    <ComplexSource><SourceFilename relativeToVRT=\"1\">tiles/c.tif</SourceFilename></ComplexSource>\n"
              "    <SimpleSource><SourceFilename relativeToVRT=\"1\">./tiles/b.tif</SourceFilename></SimpleSource>\n"
              "  </VRTRasterBand>\n"
              "</VRTDataset>\n"
              "<!-- trailing comment -->\n");
    const InputList list = expandInputs({vrt, d + "/tiles/c.tif", vrt});
    EXPECT_EQ(list.paths, (Paths{d + "/tiles/b.tif", d + "/tiles/a.tif", d + "/elsewhere/d.tif", d + "/tiles/c.tif"}));
    EXPECT_EQ(list.vrtSources, (Paths{vrt}));

    // A .VRT, named relatively from a list file, resolves its sources against its own directory.
    fs::copy_file(vrt, d + "/tiles/../UPPER.VRT");
    write(d + "/lists/list.txt", "../UPPER.VRT\n");
    const InputList listed = expandInputs({d + "/tiles/c.tif"}, d + "/lists/list.txt");
    EXPECT_EQ(listed.paths, (Paths{d + "/tiles/c.tif", d + "/lists/../tiles/b.tif", d + "/lists/../tiles/a.tif",
                                   d + "/elsewhere/d.tif"}));
    EXPECT_EQ(listed.vrtSources, (Paths{d + "/lists/../UPPER.VRT"}));
}

TEST(InputList, VrtSourcesNotRelativeToTheVrtAreTakenAsTheyAre) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/work/d.tif", d + "/v/e.tif"});
    write(d + "/v/x.vrt", vrtOfBand("<SimpleSource><SourceFilename>d.tif</SourceFilename></SimpleSource>"
                                    "<SimpleSource><SourceFilename relativeToVRT=\"0\">e.tif</SourceFilename>"
                                    "</SimpleSource>"));
    WorkingDirectory cwd(d + "/work");
    // d.tif is found in the working directory; e.tif is not there (only beside the VRT).
    EXPECT_EQ(errorOf({d + "/v/x.vrt"}), d + "/v/x.vrt: e.tif: no such file");
    touch({d + "/work/e.tif"});
    EXPECT_EQ(expandInputs({d + "/v/x.vrt"}).paths, (Paths{"d.tif", "e.tif"}));
}

TEST(InputList, VrtFilenamesDecodeEntities) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch(
        {d + "/a&b.tif", d + "/\xC3\xA9t\xC3\xA9.tif", d + "/<x>.tif", d + "/q\"'.tif", d + "/c&d.tif", d + "/A.tif"});
    write(d + "/e.vrt",
          vrtOfBand(
              "<SimpleSource><SourceFilename relativeToVRT='1'>a&amp;b.tif</SourceFilename></SimpleSource>"
              "<SimpleSource><SourceFilename relativeToVRT=\"&#49;\">&#233;t&#xe9;.tif</SourceFilename></SimpleSource>"
              "<SimpleSource><SourceFilename relativeToVRT=\"1\">&lt;x&gt;.tif</SourceFilename></SimpleSource>"
              "<SimpleSource><SourceFilename relativeToVRT=\"1\">q&quot;&apos;.tif</SourceFilename></SimpleSource>"
              "<SimpleSource><SourceFilename relativeToVRT=\"1\"><![CDATA[c&d.tif]]></SourceFilename></SimpleSource>"
              "<SimpleSource><SourceFilename relativeToVRT=\"1\">&#x41;.tif</SourceFilename></SimpleSource>"
              "<SimpleSource><SourceFilename relativeToVRT=\"1\">a&#38;b.tif</SourceFilename></SimpleSource>"));
    EXPECT_EQ(expandInputs({d + "/e.vrt"}).paths, (Paths{d + "/a&b.tif", d + "/\xC3\xA9t\xC3\xA9.tif", d + "/<x>.tif",
                                                         d + "/q\"'.tif", d + "/c&d.tif", d + "/A.tif"}));
}

TEST(InputList, VrtMissingSourceNamesTheVrtAndTheFile) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/tile_1.tif", d + "/tile_2.tif"});
    const std::string sources =
        "<SimpleSource><SourceFilename relativeToVRT=\"1\">tile_1.tif</SourceFilename></SimpleSource>"
        "<SimpleSource><SourceFilename relativeToVRT=\"1\">tile_3.tif</SourceFilename></SimpleSource>";
    write(d + "/tiles.vrt", vrtOfBand(sources));
    EXPECT_EQ(errorOf({d + "/tiles.vrt"}), d + "/tiles.vrt: " + d + "/tile_3.tif: no such file");
    write(d + "/list.txt", "tile_2.tif\ntiles.vrt\n");
    EXPECT_EQ(errorOf({}, d + "/list.txt"), d + "/list.txt:2: " + d + "/tiles.vrt: " + d + "/tile_3.tif: no such file");
    {
        WorkingDirectory cwd(d);
        EXPECT_EQ(errorOf({"tiles.vrt"}), "tiles.vrt: tile_3.tif: no such file");
    }
    fs::create_directories(d + "/tile_3.tif");
    EXPECT_EQ(errorOf({d + "/tiles.vrt"}), d + "/tiles.vrt: " + d + "/tile_3.tif: not a regular file");
    EXPECT_EQ(errorOf({d + "/none.vrt"}), d + "/none.vrt: no such file");
}

TEST(InputList, NestedVrtsGiveTheirSourcesAndCyclesAreRefused) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/a.tif", d + "/sub/b.tif"});
    write(d + "/sub/inner.vrt",
          vrtOfBand("<SimpleSource><SourceFilename relativeToVRT=\"1\">b.tif</SourceFilename></SimpleSource>"));
    write(d + "/outer.vrt",
          vrtOfBand("<SimpleSource><SourceFilename relativeToVRT=\"1\">sub/inner.vrt</SourceFilename></SimpleSource>"
                    "<SimpleSource><SourceFilename relativeToVRT=\"1\">a.tif</SourceFilename></SimpleSource>"
                    "<SimpleSource><SourceFilename relativeToVRT=\"1\">sub/inner.vrt</SourceFilename></SimpleSource>"));
    const InputList list = expandInputs({d + "/outer.vrt"});
    EXPECT_EQ(list.paths, (Paths{d + "/sub/b.tif", d + "/a.tif"}));
    EXPECT_EQ(list.vrtSources, (Paths{d + "/outer.vrt"}));

    write(d + "/x.vrt",
          vrtOfBand("<SimpleSource><SourceFilename relativeToVRT=\"1\">y.vrt</SourceFilename></SimpleSource>"));
    write(d + "/y.vrt",
          vrtOfBand("<SimpleSource><SourceFilename relativeToVRT=\"1\">a.tif</SourceFilename></SimpleSource>"
                    "<SimpleSource><SourceFilename relativeToVRT=\"1\">./x.vrt</SourceFilename></SimpleSource>"));
    EXPECT_EQ(errorOf({d + "/x.vrt"}),
              d + "/x.vrt: " + d + "/y.vrt: " + d + "/./x.vrt: the VRT is, through its sources, a source of itself");
}

struct Refusal {
    const char* what;
    std::string vrt;    // the whole file
    std::string reason; // the message after "VRT: "
};

// gdalbuildvrt over files of several resolutions trims a source's rectangle by a fraction of a
// pixel where the file reaches past the VRT's extent (rounded to whole VRT pixels): the source is
// still the whole file.
TEST(InputList, VrtSourcesTrimmedByLessThanAPixelAreWholeFiles) {
    test::TempDir dir;
    const std::string d = dir.path();
    touch({d + "/w.tif", d + "/e.tif"});
    write(d + "/mosaic.vrt",
          vrtOfBand("<ComplexSource><SourceFilename relativeToVRT=\"1\">w.tif</SourceFilename>"
                    "<SourceProperties RasterXSize=\"770\" RasterYSize=\"879\"/>"
                    "<SrcRect xOff=\"0\" yOff=\"0\" xSize=\"770\" ySize=\"879\"/></ComplexSource>"
                    "<ComplexSource><SourceFilename relativeToVRT=\"1\">e.tif</SourceFilename>"
                    "<SourceProperties RasterXSize=\"664\" RasterYSize=\"907\"/>"
                    "<SrcRect xOff=\"0.4\" yOff=\"0\" xSize=\"663.6\" ySize=\"906.865204834008\"/>"
                    "</ComplexSource>"));
    const InputList list = expandInputs({d + "/mosaic.vrt"});
    EXPECT_EQ(list.paths, (Paths{d + "/w.tif", d + "/e.tif"}));
}

TEST(InputList, VrtRefusalsNameTheVrtAndTheReason) {
    const auto simple = [](const std::string& name) {
        return "<SimpleSource><SourceFilename relativeToVRT=\"1\">" + name + "</SourceFilename></SimpleSource>";
    };
    const auto complexWith = [](const std::string& inside) {
        return "<ComplexSource><SourceFilename relativeToVRT=\"1\">a.tif</SourceFilename>" + inside +
               "</ComplexSource>";
    };
    const std::vector<Refusal> refusals = {
        {"another root", "<GDALDataset><VRTRasterBand>" + simple("a.tif") + "</VRTRasterBand></GDALDataset>",
         "the root element is <GDALDataset>, not <VRTDataset>"},
        {"a derived band",
         "<VRTDataset><VRTRasterBand band=\"1\">" + simple("a.tif") +
             "</VRTRasterBand><VRTRasterBand subClass=\"VRTDerivedRasterBand\">" + simple("a.tif") +
             "<PixelFunctionType>inv</PixelFunctionType></VRTRasterBand></VRTDataset>",
         "band 2 is a VRTDerivedRasterBand (subClass): derived and warped bands are not read"},
        {"a warped dataset",
         "<VRTDataset subClass=\"VRTWarpedDataset\"><VRTRasterBand subClass=\"VRTWarpedRasterBand\"/></VRTDataset>",
         "a VRTWarpedDataset (subClass): only plain VRTDatasets are read"},
        {"a kernel-filtered source",
         vrtOfBand(simple("a.tif") + "<KernelFilteredSource><SourceFilename relativeToVRT=\"1\">a.tif</SourceFilename>"
                                     "<Kernel><Size>3</Size></Kernel></KernelFilteredSource>"),
         "band 1: a <KernelFilteredSource>: only <SimpleSource> and <ComplexSource> are read"},
        {"an averaged source", vrtOfBand("<AveragedSource><SourceFilename>a.tif</SourceFilename></AveragedSource>"),
         "band 1: a <AveragedSource>: only <SimpleSource> and <ComplexSource> are read"},
        {"another band of the file", vrtOfBand(complexWith("<SourceBand>2</SourceBand>")),
         "band 1: the <ComplexSource> of 'a.tif' takes its band 2 as band 1; only bands as they are in the files are "
         "read (choose a DEM's band with --band)"},
        {"a mask band of the file", vrtOfBand(complexWith("<SourceBand>mask,1</SourceBand>")),
         "band 1: the <ComplexSource> of 'a.tif' takes its band mask,1 as band 1; only bands as they are in the files "
         "are read (choose a DEM's band with --band)"},
        {"a crop", vrtOfBand(complexWith("<SrcRect xOff=\"10\" yOff=\"0\" xSize=\"20\" ySize=\"20\"/>")),
         "band 1: the <ComplexSource> of 'a.tif' starts at pixel (10, 0) of the file (<SrcRect>); only whole files "
         "are read"},
        {"part of the file", vrtOfBand(complexWith("<SourceProperties RasterXSize=\"30\" RasterYSize=\"20\"/>"
                                                   "<SrcRect xOff=\"0\" yOff=\"0\" xSize=\"20\" ySize=\"20\"/>")),
         "band 1: the <ComplexSource> of 'a.tif' takes 20 x 20 of its 30 x 20 pixels (<SrcRect>); only whole files are "
         "read"},
        {"a pixel and more trimmed", vrtOfBand(complexWith("<SourceProperties RasterXSize=\"664\" RasterYSize=\"907\"/>"
                                                           "<SrcRect xOff=\"0\" yOff=\"0\" xSize=\"664\" "
                                                           "ySize=\"905.9\"/>")),
         "band 1: the <ComplexSource> of 'a.tif' takes 664 x 905.9 of its 664 x 907 pixels (<SrcRect>); only whole "
         "files are read"},
        {"a scale ratio", vrtOfBand(complexWith("<ScaleRatio>2</ScaleRatio>")),
         "band 1: the <ComplexSource> of 'a.tif' changes its values (ScaleRatio 2); only unscaled sources are read"},
        {"a scale ratio that is no number", vrtOfBand(complexWith("<ScaleRatio>one</ScaleRatio>")),
         "band 1: the <ComplexSource> of 'a.tif' changes its values (ScaleRatio one); only unscaled sources are read"},
        {"a scale offset", vrtOfBand(complexWith("<ScaleOffset>-5.5</ScaleOffset><ScaleRatio>1</ScaleRatio>")),
         "band 1: the <ComplexSource> of 'a.tif' changes its values (ScaleOffset -5.5); only unscaled sources are "
         "read"},
        {"a LUT", vrtOfBand(complexWith("<LUT>0:0,1:10</LUT>")),
         "band 1: the <ComplexSource> of 'a.tif' changes its values (<LUT>); only unscaled sources are read"},
        {"an exponent", vrtOfBand(complexWith("<Exponent>0.5</Exponent>")),
         "band 1: the <ComplexSource> of 'a.tif' changes its values (<Exponent>); only unscaled sources are read"},
        {"a colour table expansion", vrtOfBand(complexWith("<ColorTableComponent>1</ColorTableComponent>")),
         "band 1: the <ComplexSource> of 'a.tif' changes its values (<ColorTableComponent>); only unscaled sources are "
         "read"},
        {"two file names",
         vrtOfBand("<SimpleSource><SourceFilename>a.tif</SourceFilename><SourceFilename>m.tif</SourceFilename></"
                   "SimpleSource>"),
         "band 1: a <SimpleSource> with 2 <SourceFilename>"},
        {"a /vsi file", vrtOfBand(simple("/vsizip/tiles.zip/a.tif")),
         "band 1: source '/vsizip/tiles.zip/a.tif' is not a plain file (GDAL virtual file systems and URLs are not "
         "read)"},
        {"a URL", vrtOfBand("<SimpleSource><SourceFilename>https://example.com/a.tif</SourceFilename></SimpleSource>"),
         "band 1: source 'https://example.com/a.tif' is not a plain file (GDAL virtual file systems and URLs are not "
         "read)"},
        {"a band without sources", vrtOfBand("<NoDataValue>0</NoDataValue>"),
         "no source file (no <SimpleSource> or <ComplexSource> in a <VRTRasterBand>)"},
        {"no band", "<VRTDataset rasterXSize=\"1\" rasterYSize=\"1\"/>",
         "no source file (no <SimpleSource> or <ComplexSource> in a <VRTRasterBand>)"},
        {"a mask band",
         "<VRTDataset><VRTRasterBand>" + simple("a.tif") + "</VRTRasterBand><MaskBand><VRTRasterBand>" +
             simple("m.tif") + "</VRTRasterBand></MaskBand></VRTDataset>",
         "a <MaskBand>: masks are not read"},
        {"a source without a file", vrtOfBand("<SimpleSource><SourceBand>1</SourceBand></SimpleSource>"),
         "band 1: a <SimpleSource> without <SourceFilename>"},
        {"an empty file name", vrtOfBand("<ComplexSource><SourceFilename>  </SourceFilename></ComplexSource>"),
         "band 1: a <ComplexSource> with an empty <SourceFilename>"},
        {"relativeToVRT neither 0 nor 1",
         vrtOfBand("<SimpleSource><SourceFilename relativeToVRT=\"yes\">a.tif</SourceFilename></SimpleSource>"),
         "band 1: source 'a.tif' has relativeToVRT=\"yes\", neither 0 nor 1"},
        // Malformed XML, with the line of the fault.
        {"an empty file", "", "malformed XML (line 1: no root element)"},
        {"not XML", "GTiff raster", "malformed XML (line 1: text before the root element)"},
        {"an unclosed root", "<VRTDataset>\n<VRTRasterBand>" + simple("a.tif") + "</VRTRasterBand>\n",
         "malformed XML (line 1: <VRTDataset> is never closed)"},
        {"a mismatched end tag",
         "<VRTDataset>\n<VRTRasterBand>\n" + simple("a.tif") + "\n</VRTRasterBnad>\n</VRTDataset>",
         "malformed XML (line 4: </VRTRasterBnad> closes <VRTRasterBand>)"},
        {"an unknown entity", vrtOfBand(simple("a&nbsp;b.tif")), "malformed XML (line 3: unknown entity '&nbsp;')"},
        {"a bare ampersand", vrtOfBand(simple("a & b.tif")),
         "malformed XML (line 3: '&' that starts no entity (write &amp;))"},
        {"a NUL reference", vrtOfBand(simple("a&#0;.tif")),
         "malformed XML (line 3: '&#0;' is not a character XML allows)"},
        {"a surrogate reference", vrtOfBand(simple("a&#xD800;.tif")),
         "malformed XML (line 3: '&#xD800;' is not a character XML allows)"},
        {"an unterminated comment", "<VRTDataset>\n<!-- no end\n</VRTDataset>",
         "malformed XML (line 2: unterminated comment)"},
        {"an unquoted attribute", "<VRTDataset rasterXSize=10></VRTDataset>",
         "malformed XML (line 1: attribute rasterXSize of <VRTDataset> has no quoted value)"},
        {"an unterminated attribute", "<VRTDataset rasterXSize=\"10></VRTDataset>",
         "malformed XML (line 1: '<' in the value of attribute rasterXSize)"},
        {"a duplicated attribute",
         vrtOfBand("<SimpleSource><SourceFilename relativeToVRT=\"1\" "
                   "relativeToVRT=\"0\">a.tif</SourceFilename></SimpleSource>"),
         "malformed XML (line 3: attribute relativeToVRT given twice in <SourceFilename>)"},
        {"attributes without space between", "<VRTDataset a=\"1\"b=\"2\"></VRTDataset>",
         "malformed XML (line 1: expected whitespace, '>' or '/>' in <VRTDataset>)"},
        {"two roots", vrtOfBand(simple("a.tif")) + "<VRTDataset/>",
         "malformed XML (line 6: content after the root element)"},
        {"text after the root", vrtOfBand(simple("a.tif")) + "x",
         "malformed XML (line 6: content after the root element)"},
    };
    test::TempDir dir;
    touch({dir.file("a.tif"), dir.file("m.tif")});
    const std::string vrt = dir.file("refused.vrt");
    for (const Refusal& r : refusals) {
        write(vrt, r.vrt);
        EXPECT_EQ(errorOf({vrt}), vrt + ": " + r.reason) << r.what;
    }
    // A refused VRT found through a list file is named after the line.
    write(vrt, vrtOfBand(simple("/vsicurl/a.tif")));
    write(dir.file("list.txt"), "a.tif\nrefused.vrt\n");
    EXPECT_EQ(
        errorOf({}, dir.file("list.txt")),
        dir.file("list.txt") + ":2: " + vrt +
            ": band 1: source '/vsicurl/a.tif' is not a plain file (GDAL virtual file systems and URLs are not read)");
}

TEST(InputList, VrtNamesAreComparedIgnoringCaseAsGdalDoes) {
    test::TempDir dir;
    touch({dir.file("a.tif"), dir.file("b.tif")});
    write(dir.file("lower.vrt"),
          "<vrtdataset><vrtrasterband><simplesource><sourcefilename relativetovrt=\"1\">a.tif"
          "</sourcefilename></simplesource><COMPLEXSOURCE><SOURCEFILENAME RELATIVETOVRT='1'>b.tif"
          "</SOURCEFILENAME><SCALERATIO>1</SCALERATIO></COMPLEXSOURCE></vrtrasterband></vrtdataset>");
    EXPECT_EQ(expandInputs({dir.file("lower.vrt")}).paths, (Paths{dir.file("a.tif"), dir.file("b.tif")}));
}

} // namespace
} // namespace pyramid
