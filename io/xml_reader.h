// Reading attributes of tinyxml2 elements with errors that name the file,
// the line and the attribute; shared by every XML format skidsim reads.
#pragma once

#include <tinyxml2.h>

#include <Eigen/Core>

#include <set>
#include <string>

#include "io/atomic_file.h"

namespace skidsim::io {

[[noreturn]] void fail_at(const std::string& path, const tinyxml2::XMLElement* e, const std::string& what);

// Loads `path` or throws InputError with the line and the reason: not a
// regular file, too large (io/input_file.h), not UTF-8, or tinyxml2's message.
void load_xml(tinyxml2::XMLDocument& doc, const std::string& path);
// The same for `text` already read from `path` (read_input_file), for a
// caller that hands the same bytes to another parser too (the URDF).
void parse_xml(tinyxml2::XMLDocument& doc, const std::string& path, const std::string& text);

// Parses one decimal number from `text` (blanks first), advancing past it;
// false, with `text` unmoved, unless a finite decimal number is there (hex,
// inf and nan are not numbers in skidsim's files).
bool parse_decimal_number(const char*& text, double& value);

// The one bound for positions and extents read from any file (metres): far
// past any site (2 km) and the roads beyond it, near enough that every
// product of two stays far from overflow.
constexpr double kMaxCoordinate_m = 1.0e5;

// Reads the attributes of one element and checks that every attribute it
// has is one the caller asked for (a typo must not pass silently).
class AttributeReader {
 public:
  AttributeReader(std::string path, const tinyxml2::XMLElement* e) : path_(std::move(path)), e_(e) {}
  // Every number has a physical range, checked where it enters: a finite
  // value that parses whole ("33deg" fails) in [lo, hi].
  double number_in(const char* name, double lo, double hi);
  // The same, or `fallback` when the attribute is absent.
  double number_in_or(const char* name, double lo, double hi, double fallback);
  // "x y z", three numbers each in [lo, hi], separated by spaces.
  Eigen::Vector3d vector3_in(const char* name, double lo, double hi);
  // Exactly `count` numbers each in [lo, hi] ("x y", "x0 y0 x1 y1").
  Eigen::VectorXd numbers_in(const char* name, int count, double lo, double hi);
  bool has(const char* name) const { return e_->Attribute(name) != nullptr; }
  bool boolean_or(const char* name, bool fallback);
  std::string text(const char* name, bool required);
  void reject_unknown() const;
  // An element whose content means nothing (a leaf) must have none: a phase
  // nested in a phase, or text, would otherwise be silently ignored.
  void reject_content() const;
  [[noreturn]] void fail(const std::string& what) const { fail_at(path_, e_, what); }

 private:
  double number(const char* name);  // finite, unbounded: callers give a range
  void check_range(const char* name, double v, double lo, double hi) const;
  std::string path_;
  const tinyxml2::XMLElement* e_;
  std::set<std::string> known_;
};

}  // namespace skidsim::io
