#include "io/heightmap.h"
#include "io/png_image.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "io/atomic_file.h"
#include "io/input_file.h"
#include "io/json_file.h"
#include "io/png_reader.h"
#include "io/xml_reader.h"
#include "terrain/granular_grid.h"

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

// The image's pixels, row 0 first. Its header (size, bit depth, colour
// type) is compared with the metadata before any pixel buffer is made: a
// header may claim 100000 x 100000 pixels in a file of a few bytes.
std::vector<std::uint16_t> read_png16(const std::string& png_path, const std::string& json_path, int nx, int ny) {
  PngReader reader(png_path, "height map image");
  png_structp png = reader.png;
  png_infop info = reader.info;
  // libpng reports errors by longjmp: the buffers live behind a pointer made
  // before setjmp, so nothing set up after it is skipped or left undefined.
  struct Buffers {
    std::vector<std::uint16_t> pixels;
    std::vector<png_bytep> rows;
  };
  const auto buffers = std::make_unique<Buffers>();
  if (setjmp(png_jmpbuf(png))) throw InputError(reader.corrupt());
  png_read_info(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  const int color = png_get_color_type(png, info);
  if (bit_depth != 16 || color != PNG_COLOR_TYPE_GRAY) {
    std::ostringstream msg;
    msg << png_path << ": height maps must be 16-bit greyscale PNG (found bit depth " << bit_depth
        << ", colour type " << color << ")";
    throw InputError(msg.str());
  }
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  if (width != static_cast<png_uint_32>(nx) || height != static_cast<png_uint_32>(ny)) {
    std::ostringstream msg;
    msg << json_path << ": fields 'nx', 'ny' = " << nx << " x " << ny << " do not match image " << png_path
        << " (its header says " << width << " x " << height << ")";
    throw InputError(msg.str());
  }
  png_set_swap(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != static_cast<std::size_t>(nx) * sizeof(std::uint16_t))
    throw InputError(png_path + ": cannot read it as 16-bit greyscale");
  buffers->pixels.resize(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  buffers->rows.resize(static_cast<std::size_t>(ny));
  for (int r = 0; r < ny; ++r)
    buffers->rows[static_cast<std::size_t>(r)] =
        reinterpret_cast<png_bytep>(&buffers->pixels[static_cast<std::size_t>(r) * static_cast<std::size_t>(nx)]);
  png_read_image(png, buffers->rows.data());
  png_read_end(png, nullptr);
  return std::move(buffers->pixels);
}

// The metadata's fields. Each is checked where it enters: its type (a
// number given as a string, or an integer given as 9.5, is refused, not
// converted), finiteness and physical range; errors name the file and the
// field.
const std::set<std::string>& known_fields() {
  static const std::set<std::string> fields = {"format", "version", "image", "quantity", "nx", "ny", "cell_size_m",
                                               "origin_m", "z_offset_m", "vertical_scale_m",
                                               // descriptive text the writer adds
                                               "row_order", "metres"};
  return fields;
}
const char* const kRequiredFields[] = {"format", "version", "image", "quantity", "nx", "ny",
                                       "cell_size_m", "origin_m", "z_offset_m", "vertical_scale_m"};

// A value or name for a message: at most 64 characters of it (a field
// may hold a 60 MB array).
std::string shown(const std::string& text) {
  if (text.size() <= 64) return text;
  std::size_t cut = 61;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0u) == 0x80u) --cut;  // whole UTF-8 characters
  return text.substr(0, cut) + "...";
}
std::string shown(const json& v) { return shown(v.dump(-1, ' ', false, json::error_handler_t::replace)); }

[[noreturn]] void bad_field(const std::string& path, const char* key, const json& v, const std::string& what) {
  throw InputError(path + ": field '" + key + "' = " + shown(v) + ": " + what);
}

std::string text_field(const json& meta, const std::string& path, const char* key) {
  const json& v = meta.at(key);
  if (!v.is_string()) bad_field(path, key, v, std::string("expected a string, found ") + v.type_name());
  return v.get<std::string>();
}

long long integer_field(const json& meta, const std::string& path, const char* key, long long lo, long long hi) {
  const json& v = meta.at(key);
  if (!v.is_number_integer())
    bad_field(path, key, v, v.is_number() ? std::string("expected a whole number (no point or exponent)")
                                          : std::string("expected a whole number, found ") + v.type_name());
  // Unsigned values past int64 are compared as unsigned: none is in range.
  if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(hi))
    bad_field(path, key, v, "out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  const long long n = v.get<long long>();
  if (n < lo || n > hi) bad_field(path, key, v, "out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return n;
}

double finite_number(const json& v, const std::string& path, const char* key) {
  if (!v.is_number()) bad_field(path, key, v, std::string("expected a number, found ") + v.type_name());
  const double x = v.get<double>();
  if (!std::isfinite(x)) bad_field(path, key, v, "not a finite number");
  return x;
}

double checked_number(const json& v, const std::string& path, const char* key, double lo, double hi, const char* unit) {
  const double x = finite_number(v, path, key);
  if (!(x >= lo && x <= hi)) {
    std::ostringstream msg;
    msg << "out of range [" << lo << ", " << hi << "] " << unit;
    bad_field(path, key, v, msg.str());
  }
  return x;
}

// The range of heights the automaton takes for each quantity
// (terrain/granular_grid.h): a material column of 0 to kMaxColumnM, a base
// within kMaxBaseAbsM, a surface (base plus material) within both.
struct HeightLimits {
  double lo_m, hi_m;
  const char* noun;
};
HeightLimits height_limits(const std::string& quantity) {
  if (quantity == "material") return {0.0, terrain::kMaxColumnM, "material depth"};
  if (quantity == "base") return {-terrain::kMaxBaseAbsM, terrain::kMaxBaseAbsM, "base height"};
  return {-terrain::kMaxBaseAbsM, terrain::kMaxBaseAbsM + terrain::kMaxColumnM, "surface height"};
}

json parse_metadata(const std::string& path) { return read_json_file(path, "height map metadata"); }

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
  const json meta = parse_metadata(json_path);
  if (!meta.is_object())
    throw InputError(json_path + ": expected a JSON object of height map fields, found " + meta.type_name());
  for (const auto& item : meta.items())
    if (!known_fields().count(item.key())) throw InputError(json_path + ": unknown field '" + shown(item.key()) + "'");
  std::string missing;
  for (const char* key : kRequiredFields)
    if (!meta.contains(key)) missing += std::string(missing.empty() ? "" : ", ") + "'" + key + "'";
  if (!missing.empty()) throw InputError(json_path + ": missing field(s) " + missing);
  for (const char* key : {"row_order", "metres"})
    if (meta.contains(key)) text_field(meta, json_path, key);

  if (text_field(meta, json_path, "format") != "skidsim-heightmap")
    bad_field(json_path, "format", meta.at("format"), "expected \"skidsim-heightmap\"");
  integer_field(meta, json_path, "version", 1, 1);
  Heightmap map;
  map.quantity = text_field(meta, json_path, "quantity");
  if (map.quantity != "surface" && map.quantity != "material" && map.quantity != "base")
    bad_field(json_path, "quantity", meta.at("quantity"), "expected \"surface\", \"material\" or \"base\"");
  // The same cap on a side as a site given on the command line.
  map.nx = static_cast<int>(integer_field(meta, json_path, "nx", 1, kMaxSiteCellsPerSide));
  map.ny = static_cast<int>(integer_field(meta, json_path, "ny", 1, kMaxSiteCellsPerSide));
  map.cell_size_m = checked_number(meta.at("cell_size_m"), json_path, "cell_size_m", kMinHeightmapCell_m,
                                   kMaxHeightmapCell_m, "m");
  {
    const json& origin = meta.at("origin_m");
    if (!origin.is_array() || origin.size() != 2)
      bad_field(json_path, "origin_m", origin, "expected [x, y] (two numbers, metres)");
    for (int k = 0; k < 2; ++k)
      map.origin_m[k] = checked_number(origin[static_cast<std::size_t>(k)], json_path, "origin_m", -kMaxCoordinate_m,
                                       kMaxCoordinate_m, "m");
    // The far corner too: the whole grid lies where positions are bounded.
    const Eigen::Vector2d far = map.origin_m + map.cell_size_m * Eigen::Vector2d(map.nx - 1, map.ny - 1);
    if (!(far.cwiseAbs().maxCoeff() <= kMaxCoordinate_m)) {
      std::ostringstream msg;
      msg << "the grid's far cell lies at (" << far.x() << ", " << far.y() << ") m, beyond +-" << kMaxCoordinate_m
          << " m (fields 'nx', 'ny', 'cell_size_m')";
      bad_field(json_path, "origin_m", origin, msg.str());
    }
  }
  const HeightLimits limits = height_limits(map.quantity);
  // The offset is the height of pixel 0: within the quantity's limits.
  const double z_offset = finite_number(meta.at("z_offset_m"), json_path, "z_offset_m");
  if (!(z_offset >= limits.lo_m && z_offset <= limits.hi_m)) {
    std::ostringstream msg;
    msg << "the " << limits.noun << " it gives is not within [" << limits.lo_m << ", " << limits.hi_m << "] m";
    bad_field(json_path, "z_offset_m", meta.at("z_offset_m"), msg.str());
  }
  // At most a 10 m step: a base spanning the whole +-100 km over 16 bits
  // needs 3.1 m.
  const double scale = checked_number(meta.at("vertical_scale_m"), json_path, "vertical_scale_m", 1e-9, 10.0, "m");
  const std::string image = text_field(meta, json_path, "image");
  if (image.empty()) bad_field(json_path, "image", meta.at("image"), "names no file");

  const std::string png_path = image[0] == '/' ? image : dir_of(json_path) + "/" + image;
  // The image's errors name the metadata that names it too: the user opened that file.
  std::vector<std::uint16_t> pixels;
  try {
    pixels = read_png16(png_path, json_path, map.nx, map.ny);
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.find(json_path) != std::string::npos) throw;
    throw InputError(json_path + ": field 'image' = \"" + shown(image) + "\": " + what);
  }
  map.height_m.resize(pixels.size());
  for (int j = 0; j < map.ny; ++j) {
    const int row = map.ny - 1 - j;
    for (int i = 0; i < map.nx; ++i) {
      const std::uint16_t pixel = pixels[static_cast<std::size_t>(row) * map.nx + i];
      const double h = z_offset + scale * pixel;
      if (!(h >= limits.lo_m && h <= limits.hi_m)) {
        std::ostringstream msg;
        msg << json_path << ": " << limits.noun << " " << h << " m at cell (" << i << ", " << j << ") (pixel " << pixel
            << " of " << png_path << ") is not within [" << limits.lo_m << ", " << limits.hi_m
            << "] m (fields 'z_offset_m', 'vertical_scale_m')";
        throw InputError(msg.str());
      }
      map.height_m[static_cast<std::size_t>(j) * map.nx + i] = h;
    }
  }
  return map;
}

}  // namespace skidsim::io
