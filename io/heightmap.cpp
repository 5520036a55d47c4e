#include "io/heightmap.h"
#include "io/png_image.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/atomic_file.h"
#include "io/png_reader.h"

namespace skidsim::io {
namespace {

using nlohmann::json;

std::string file_name_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string dir_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

void write_png16(const std::string& path, int width, int height, const std::vector<std::uint16_t>& rows) {
  write_png_rows(path, width, height, 16, PNG_COLOR_TYPE_GRAY, reinterpret_cast<const std::uint8_t*>(rows.data()),
                 static_cast<std::size_t>(width) * sizeof(std::uint16_t));
}

std::vector<std::uint16_t> read_png16(const std::string& path, int& width, int& height) {
  PngReader reader(path, "height map image");
  png_structp png = reader.png;
  png_infop info = reader.info;
  // libpng reports errors by longjmp: the buffers live behind a pointer made
  // before setjmp, so nothing set up after it is skipped or left undefined.
  struct Buffers {
    std::vector<std::uint16_t> pixels;
    std::vector<png_bytep> rows;
  };
  const auto buffers = std::make_unique<Buffers>();
  if (setjmp(png_jmpbuf(png))) throw InputError(path + ": corrupt or truncated PNG");
  png_read_info(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  const int color = png_get_color_type(png, info);
  if (bit_depth != 16 || color != PNG_COLOR_TYPE_GRAY) {
    std::ostringstream msg;
    msg << path << ": height maps must be 16-bit greyscale PNG (found bit depth " << bit_depth
        << ", colour type " << color << ")";
    throw InputError(msg.str());
  }
  width = static_cast<int>(png_get_image_width(png, info));
  height = static_cast<int>(png_get_image_height(png, info));
  png_set_swap(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  buffers->pixels.resize(static_cast<std::size_t>(width) * height);
  buffers->rows.resize(static_cast<std::size_t>(height));
  for (int r = 0; r < height; ++r)
    buffers->rows[static_cast<std::size_t>(r)] =
        reinterpret_cast<png_bytep>(&buffers->pixels[static_cast<std::size_t>(r) * width]);
  png_read_image(png, buffers->rows.data());
  png_read_end(png, nullptr);
  return std::move(buffers->pixels);
}

template <typename T>
T field(const json& meta, const char* key, const std::string& path) {
  if (!meta.contains(key)) throw InputError(path + ": missing field '" + key + "'");
  try {
    return meta.at(key).get<T>();
  } catch (const json::exception&) {
    throw InputError(path + ": field '" + key + "' has the wrong type");
  }
}

}  // namespace

HeightmapFileInfo write_heightmap(const std::string& path_stem, const Heightmap& map,
                                  double min_vertical_scale_m) {
  if (map.nx < 1 || map.ny < 1 || map.height_m.size() != static_cast<std::size_t>(map.nx) * map.ny)
    throw std::invalid_argument("write_heightmap: size does not match nx * ny");
  double lo = map.height_m[0], hi = map.height_m[0];
  for (double h : map.height_m) {
    if (!std::isfinite(h)) throw std::invalid_argument("write_heightmap: non-finite height");
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  HeightmapFileInfo info;
  info.z_offset_m = lo;
  info.vertical_scale_m = std::max((hi - lo) / 65535.0, min_vertical_scale_m);

  std::vector<std::uint16_t> rows(map.height_m.size());
  for (int j = 0; j < map.ny; ++j) {
    const int row = map.ny - 1 - j;
    for (int i = 0; i < map.nx; ++i) {
      const double v = std::round((map.at(i, j) - lo) / info.vertical_scale_m);
      rows[static_cast<std::size_t>(row) * map.nx + i] = static_cast<std::uint16_t>(std::clamp(v, 0.0, 65535.0));
    }
  }
  const std::string png_path = path_stem + ".png";
  write_atomically(png_path, [&](const std::string& tmp) { write_png16(tmp, map.nx, map.ny, rows); });

  json meta = {
      {"format", "skidsim-heightmap"},
      {"version", 1},
      {"image", file_name_of(png_path)},
      {"quantity", map.quantity},
      {"nx", map.nx},
      {"ny", map.ny},
      {"cell_size_m", map.cell_size_m},
      {"origin_m", {map.origin_m.x(), map.origin_m.y()}},
      {"z_offset_m", info.z_offset_m},
      {"vertical_scale_m", info.vertical_scale_m},
      {"row_order", "row 0 is the largest y (north up); column 0 is the smallest x"},
      {"metres", "z_offset_m + vertical_scale_m * pixel"},
  };
  write_text_atomically(path_stem + ".json", meta.dump(2) + "\n");
  return info;
}

Heightmap read_heightmap(const std::string& json_path) {
  std::ifstream in(json_path);
  if (!in) throw InputError(json_path + ": cannot open height map metadata");
  json meta;
  try {
    meta = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(json_path + ": invalid JSON (" + e.what() + ")");
  }
  if (!meta.is_object() || meta.value("format", std::string()) != "skidsim-heightmap")
    throw InputError(json_path + ": field 'format' must be \"skidsim-heightmap\"");
  const int version = field<int>(meta, "version", json_path);
  if (version != 1) throw InputError(json_path + ": field 'version' = " + std::to_string(version) + " is not supported (expected 1)");

  Heightmap map;
  map.nx = field<int>(meta, "nx", json_path);
  map.ny = field<int>(meta, "ny", json_path);
  map.cell_size_m = field<double>(meta, "cell_size_m", json_path);
  map.quantity = field<std::string>(meta, "quantity", json_path);
  const auto origin = field<std::vector<double>>(meta, "origin_m", json_path);
  const double z_offset = field<double>(meta, "z_offset_m", json_path);
  const double scale = field<double>(meta, "vertical_scale_m", json_path);
  const std::string image = field<std::string>(meta, "image", json_path);
  if (origin.size() != 2 || !std::isfinite(origin[0]) || !std::isfinite(origin[1]))
    throw InputError(json_path + ": field 'origin_m' must be [x, y] with finite x and y");
  if (!(map.cell_size_m > 0.0) || !std::isfinite(map.cell_size_m))
    throw InputError(json_path + ": field 'cell_size_m' must be a finite number > 0");
  if (map.nx < 1 || map.ny < 1) throw InputError(json_path + ": fields 'nx', 'ny' must be >= 1");
  if (!(scale > 0.0) || !std::isfinite(scale)) throw InputError(json_path + ": field 'vertical_scale_m' must be > 0");
  if (!std::isfinite(z_offset)) throw InputError(json_path + ": field 'z_offset_m' must be finite");
  if (map.quantity != "surface" && map.quantity != "material" && map.quantity != "base")
    throw InputError(json_path + ": field 'quantity' must be surface, material or base");
  map.origin_m = {origin[0], origin[1]};

  const std::string png_path = image.empty() || image[0] == '/' ? image : dir_of(json_path) + "/" + image;
  int width = 0, height = 0;
  const std::vector<std::uint16_t> pixels = read_png16(png_path, width, height);
  if (width != map.nx || height != map.ny) {
    std::ostringstream msg;
    msg << json_path << ": fields 'nx', 'ny' = " << map.nx << " x " << map.ny << " do not match image "
        << png_path << " (" << width << " x " << height << ")";
    throw InputError(msg.str());
  }
  map.height_m.resize(pixels.size());
  for (int j = 0; j < map.ny; ++j) {
    const int row = map.ny - 1 - j;
    for (int i = 0; i < map.nx; ++i)
      map.height_m[static_cast<std::size_t>(j) * map.nx + i] =
          z_offset + scale * pixels[static_cast<std::size_t>(row) * map.nx + i];
  }
  return map;
}

}  // namespace skidsim::io
