// Height maps on disk: 16-bit PNG + JSON metadata, round trip and bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/heightmap.h"

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

  fs::path dir_;
};

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
