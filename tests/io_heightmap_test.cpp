// Height maps on disk: 16-bit PNG + JSON metadata, round trip and bad input.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/heightmap.h"
#include "io/png_image.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;

class HeightmapFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("skidsim_hm_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  static Heightmap sample(int nx, int ny, double cell_m) {
    Heightmap m;
    m.nx = nx;
    m.ny = ny;
    m.cell_size_m = cell_m;
    m.origin_m = {1.25, -3.5};
    m.height_m.resize(static_cast<std::size_t>(nx) * ny);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.height_m[static_cast<std::size_t>(j) * nx + i] = 2.0 + 0.8 * std::sin(0.3 * i) * std::cos(0.2 * j) + 0.01 * j;
    return m;
  }

  static void expect_error_mentions(const std::function<void()>& f, const std::vector<std::string>& words) {
    try {
      f();
      FAIL() << "expected an InputError";
    } catch (const InputError& e) {
      for (const auto& w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
    }
  }

  // The metadata of a written 8 x 8 map, to break one field at a time.
  nlohmann::json good_meta() {
    write_heightmap(path("ok"), sample(8, 8, 0.1));
    return nlohmann::json::parse(std::ifstream(path("ok.json")));
  }

  fs::path dir_;
};

// A PNG of its signature, an IHDR saying what the test likes, a two-byte
// IDAT (a zlib header, no pixels) and IEND: a header's claims with nothing
// behind them.
std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (const unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}
void put32(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((v >> shift) & 0xFFu);
}
void write_png_header_only(const std::string& path, std::uint32_t width, std::uint32_t height, int bit_depth, int colour) {
  std::string ihdr = "IHDR";
  put32(ihdr, width);
  put32(ihdr, height);
  ihdr += static_cast<char>(bit_depth);
  ihdr += static_cast<char>(colour);
  ihdr += std::string(3, '\0');  // deflate, adaptive filtering, no interlace
  std::string png = "\x89PNG\r\n\x1a\n";
  put32(png, 13);
  png += ihdr;
  put32(png, crc32(ihdr));
  const std::string idat = "IDAT\x78\x9c";
  put32(png, 2);
  png += idat;
  put32(png, crc32(idat));
  put32(png, 0);
  png += "IEND";
  put32(png, crc32("IEND"));
  std::ofstream(path, std::ios::binary) << png;
}

long peak_rss_kb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

TEST_F(HeightmapFiles, RoundTripWithinHalfAVerticalStep) {
  for (double cell : {0.05, 0.025}) {
    const Heightmap in = sample(37, 23, cell);
    const HeightmapFileInfo info = write_heightmap(path("terrain"), in);
    const Heightmap out = read_heightmap(path("terrain.json"));
    ASSERT_EQ(out.nx, in.nx);
    ASSERT_EQ(out.ny, in.ny);
    EXPECT_EQ(out.cell_size_m, cell);
    EXPECT_EQ(out.origin_m, in.origin_m);
    double worst = 0;
    for (std::size_t k = 0; k < in.height_m.size(); ++k) worst = std::max(worst, std::abs(out.height_m[k] - in.height_m[k]));
    EXPECT_LE(worst, 0.5 * info.vertical_scale_m + 1e-12);
    const auto [lo, hi] = std::minmax_element(in.height_m.begin(), in.height_m.end());
    EXPECT_DOUBLE_EQ(info.vertical_scale_m, (*hi - *lo) / 65535.0);  // the range over 16 bits
  }
}

TEST_F(HeightmapFiles, RowZeroOfTheImageIsNorth) {
  Heightmap m = sample(4, 3, 0.1);
  std::fill(m.height_m.begin(), m.height_m.end(), 0.0);
  m.height_m[2 * 4 + 0] = 1.0;  // cell (0, 2): the largest y
  write_heightmap(path("north"), m);
  const Heightmap back = read_heightmap(path("north.json"));
  EXPECT_NEAR(back.at(0, 2), 1.0, 1e-4);
  EXPECT_NEAR(back.at(0, 0), 0.0, 1e-4);
}

TEST_F(HeightmapFiles, BadInputNamesFileAndField) {
  write_heightmap(path("ok"), sample(8, 8, 0.1));
  expect_error_mentions([&] { read_heightmap(path("missing.json")); }, {"missing.json"});

  {  // nx that does not match the image
    nlohmann::json meta = nlohmann::json::parse(std::ifstream(path("ok.json")));
    meta["nx"] = 9;
    std::ofstream(path("wrong_nx.json")) << meta.dump();
    expect_error_mentions([&] { read_heightmap(path("wrong_nx.json")); }, {"wrong_nx.json", "'nx'"});
  }
  {  // missing field
    nlohmann::json meta = nlohmann::json::parse(std::ifstream(path("ok.json")));
    meta.erase("vertical_scale_m");
    std::ofstream(path("no_scale.json")) << meta.dump();
    expect_error_mentions([&] { read_heightmap(path("no_scale.json")); }, {"no_scale.json", "vertical_scale_m"});
  }
  {  // not JSON
    std::ofstream(path("garbage.json")) << "{ nx: ";
    expect_error_mentions([&] { read_heightmap(path("garbage.json")); }, {"garbage.json", "invalid JSON"});
  }
  {  // a truncated PNG
    const auto size = fs::file_size(path("ok.png"));
    fs::copy_file(path("ok.png"), path("trunc.png"));
    fs::resize_file(path("trunc.png"), size / 2);
    nlohmann::json meta = nlohmann::json::parse(std::ifstream(path("ok.json")));
    meta["image"] = "trunc.png";
    std::ofstream(path("trunc.json")) << meta.dump();
    expect_error_mentions([&] { read_heightmap(path("trunc.json")); }, {"trunc.png"});
  }
  {  // not a PNG at all
    std::ofstream(path("text.png")) << "hello";
    nlohmann::json meta = nlohmann::json::parse(std::ifstream(path("ok.json")));
    meta["image"] = "text.png";
    std::ofstream(path("text.json")) << meta.dump();
    expect_error_mentions([&] { read_heightmap(path("text.json")); }, {"text.png", "not a PNG"});
  }
}

// Every field is checked for its type, finiteness and physical range where
// it enters; a value past its range is named with the file and the field,
// never turned into NaN masses downstream (cell_size_m = 1e308 was).
TEST_F(HeightmapFiles, EveryFieldIsCheckedWhereItEnters) {
  const nlohmann::json good = good_meta();
  const std::vector<nlohmann::json> bad_values = {1e308, -1e308, "NaN", "Infinity", "1", true, nullptr,
                                                  nlohmann::json::array(), nlohmann::json::object()};
  for (const char* field : {"cell_size_m", "z_offset_m", "vertical_scale_m", "nx", "ny", "version", "origin_m"}) {
    for (const nlohmann::json& value : bad_values) {
      nlohmann::json meta = good;
      meta[field] = value;
      std::ofstream(path("bad.json"), std::ios::trunc) << meta.dump();
      SCOPED_TRACE(std::string(field) + " = " + value.dump());
      expect_error_mentions([&] { read_heightmap(path("bad.json")); }, {"bad.json", std::string("'") + field + "'"});
    }
    nlohmann::json meta = good;
    meta.erase(field);
    std::ofstream(path("missing_field.json"), std::ios::trunc) << meta.dump();
    expect_error_mentions([&] { read_heightmap(path("missing_field.json")); },
                          {"missing_field.json", "missing", std::string("'") + field + "'"});
  }
  // One bad coordinate of two; a fractional cell count; a format or quantity
  // of the wrong type.
  for (const auto& [field, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"origin_m", {0.0, 1e308}}, {"origin_m", {0.0, "NaN"}}, {"origin_m", {0.0, 0.0, 0.0}},
           {"nx", 8.5}, {"ny", 8.0}, {"nx", -8}, {"nx", 0}, {"format", 1}, {"quantity", 2}, {"image", 3},
           {"quantity", "lava"}, {"cell_size_m", 0.0}, {"cell_size_m", -0.1}, {"vertical_scale_m", 0.0}}) {
    nlohmann::json meta = good;
    meta[field] = value;
    std::ofstream(path("bad.json"), std::ios::trunc) << meta.dump();
    SCOPED_TRACE(field + " = " + value.dump());
    expect_error_mentions([&] { read_heightmap(path("bad.json")); }, {"bad.json", "'" + field + "'"});
  }
}

TEST_F(HeightmapFiles, UnknownFieldsAndBadJsonAreNamed) {
  nlohmann::json meta = good_meta();
  meta["cell_size"] = 0.1;  // a typo must not pass silently
  std::ofstream(path("typo.json")) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("typo.json")); }, {"typo.json", "unknown field 'cell_size'"});
  // A field holding a long array is shown in part.
  meta = good_meta();
  meta["origin_m"] = std::vector<double>(100000, 1.0);
  std::ofstream(path("long.json")) << meta.dump();
  try {
    read_heightmap(path("long.json"));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'origin_m' = [1.0,1.0"), std::string::npos) << e.what();
    EXPECT_LT(std::string(e.what()).size(), 400u) << e.what();
  }
  // JSON has no NaN: the parser's byte and the line are given.
  std::ofstream(path("nan.json")) << "{\n  \"format\": \"skidsim-heightmap\",\n  \"cell_size_m\": NaN\n}\n";
  expect_error_mentions([&] { read_heightmap(path("nan.json")); }, {"nan.json:3:", "invalid JSON at byte"});
  // A number past double's range parses to no finite number.
  std::string text = good_meta().dump();
  text.replace(text.find("\"cell_size_m\":") + 14, 3, "1e999");
  std::ofstream(path("huge.json")) << text;
  expect_error_mentions([&] { read_heightmap(path("huge.json")); }, {"huge.json", "invalid JSON", "1e999"});
  std::ofstream(path("array.json")) << "[1, 2]";
  expect_error_mentions([&] { read_heightmap(path("array.json")); }, {"array.json", "object"});
}

TEST_F(HeightmapFiles, NotRegularFilesAreRefusedByName) {
  fs::create_directories(path("folder.json"));
  expect_error_mentions([&] { read_heightmap(path("folder.json")); }, {"folder.json", "directory"});
  nlohmann::json meta = good_meta();
  meta["image"] = "/dev/zero";  // would read forever
  std::ofstream(path("zero.json")) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("zero.json")); }, {"/dev/zero", "not a regular file"});
}

// The same cap on a side as the command line's site: the metadata is
// refused before the image is opened.
TEST_F(HeightmapFiles, SidesPastTheSiteCapAreRefused) {
  nlohmann::json meta = good_meta();
  meta["nx"] = kMaxSiteCellsPerSide + 1;
  std::ofstream(path("wide.json")) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("wide.json")); },
                        {"wide.json", "'nx'", std::to_string(kMaxSiteCellsPerSide)});
  // Far corner beyond the coordinate bound, with each field in its own range.
  meta = good_meta();
  meta["origin_m"] = {99999.5, 0.0};  // + 7 cells of 0.1 m
  std::ofstream(path("far.json")) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("far.json")); }, {"far.json", "far cell"});
}

// A header claiming 100000 x 100000 pixels (20 GB of 16-bit samples) in a
// file of 71 bytes: compared with the metadata before any pixel buffer.
TEST_F(HeightmapFiles, PngHeaderIsComparedBeforeAnyPixelIsAllocated) {
  nlohmann::json meta = good_meta();
  meta["nx"] = 10;
  meta["ny"] = 10;
  meta["image"] = "huge.png";
  write_png_header_only(path("huge.png"), 100000, 100000, 16, 0);
  std::ofstream(path("huge.json")) << meta.dump();
  const long before_kb = peak_rss_kb();
  expect_error_mentions([&] { read_heightmap(path("huge.json")); },
                        {"huge.json", "'nx', 'ny' = 10 x 10", "huge.png", "100000 x 100000"});
  EXPECT_LT(peak_rss_kb() - before_kb, 64 * 1024) << "kB: the header's size was allocated";
  // An 8-bit image with the right size; a header past libpng's own limit.
  write_png_header_only(path("eight.png"), 10, 10, 8, 0);
  meta["image"] = "eight.png";
  std::ofstream(path("eight.json")) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("eight.json")); }, {"eight.png", "16-bit greyscale"});
  write_png_header_only(path("giant.png"), 0x7FFFFFFFu, 10, 16, 0);
  meta["image"] = "giant.png";
  std::ofstream(path("giant.json")) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("giant.json")); }, {"giant.png", "libpng"});
}

// Frames read back (the contact sheet) are held to a frame's size.
TEST_F(HeightmapFiles, ImagesReadBackAreCheckedBeforeAllocation) {
  write_png_header_only(path("poster.png"), 100000, 100000, 8, 2);
  expect_error_mentions([&] { read_png_rgb8(path("poster.png")); }, {"poster.png", "100000 x 100000"});
  fs::create_directories(path("frames.png"));
  expect_error_mentions([&] { read_png_rgb8(path("frames.png")); }, {"frames.png", "directory"});
  expect_error_mentions([&] { read_png_rgb8("/dev/zero"); }, {"/dev/zero", "not a regular file"});
  RgbImage image;
  image.width = 3;
  image.height = 2;
  image.rgb.assign(18, 200);
  write_png_rgb8(path("small.png"), image);
  EXPECT_EQ(read_png_rgb8(path("small.png")).rgb, image.rgb);
}

// Decoded heights within the automaton's limits for the quantity, named by
// cell: a material map whose steps reach past 1000 m of column.
TEST_F(HeightmapFiles, DecodedHeightsOutOfRangeNameTheCell) {
  Heightmap m = sample(8, 8, 0.1);
  m.quantity = "material";
  write_heightmap(path("deep"), m);
  nlohmann::json meta = nlohmann::json::parse(std::ifstream(path("deep.json")));
  meta["vertical_scale_m"] = 1.0;  // 65535 m at the top pixel
  std::ofstream(path("deep.json"), std::ios::trunc) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("deep.json")); }, {"deep.json", "material depth", "at cell"});
  meta["vertical_scale_m"] = 1e-6;
  meta["z_offset_m"] = -1.0;  // below the base: no material column is negative
  std::ofstream(path("deep.json"), std::ios::trunc) << meta.dump();
  expect_error_mentions([&] { read_heightmap(path("deep.json")); }, {"deep.json", "'z_offset_m'", "material depth"});
}

TEST_F(HeightmapFiles, FailedWriteLeavesNoHalfWrittenFile) {
  write_text_atomically(path("result.txt"), "complete\n");
  EXPECT_THROW(write_atomically(path("result.txt"), [](const std::string& tmp) {
                 std::ofstream(tmp) << "half";
                 throw std::runtime_error("disk full");
               }),
               std::runtime_error);
  std::ifstream in(path("result.txt"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "complete");
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace skidsim::io
