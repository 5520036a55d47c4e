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

// Loads `path` or throws InputError with tinyxml2's line and message.
void load_xml(tinyxml2::XMLDocument& doc, const std::string& path);

// Reads the attributes of one element and checks that every attribute it
// has is one the caller asked for (a typo must not pass silently).
class AttributeReader {
 public:
  AttributeReader(std::string path, const tinyxml2::XMLElement* e) : path_(std::move(path)), e_(e) {}
  // A required finite number; the whole value must parse ("33deg" fails).
  double number(const char* name);
  double number_or(const char* name, double fallback);
  // A required number in [lo, hi].
  double number_in(const char* name, double lo, double hi);
  // "x y z", three finite numbers separated by spaces.
  Eigen::Vector3d vector3(const char* name);
  // Exactly `count` finite numbers separated by spaces ("x y", "x0 y0 x1 y1").
  Eigen::VectorXd numbers(const char* name, int count);
  bool has(const char* name) const { return e_->Attribute(name) != nullptr; }
  bool boolean_or(const char* name, bool fallback);
  std::string text(const char* name, bool required);
  void reject_unknown() const;
  [[noreturn]] void fail(const std::string& what) const { fail_at(path_, e_, what); }

 private:
  std::string path_;
  const tinyxml2::XMLElement* e_;
  std::set<std::string> known_;
};

}  // namespace skidsim::io
