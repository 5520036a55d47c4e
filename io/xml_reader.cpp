#include "io/xml_reader.h"

#include "io/input_file.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace skidsim::io {

void fail_at(const std::string& path, const tinyxml2::XMLElement* e, const std::string& what) {
  std::ostringstream msg;
  msg << path << ":" << (e ? e->GetLineNum() : 0) << ": ";
  if (e) msg << "<" << e->Name() << "> ";
  msg << what;
  throw InputError(msg.str());
}

void load_xml(tinyxml2::XMLDocument& doc, const std::string& path) {
  parse_xml(doc, path, read_input_file(path, kMaxXmlBytes, "XML file"));
}

void parse_xml(tinyxml2::XMLDocument& doc, const std::string& path, const std::string& text) {
  // XML is UTF-8 here (the encoding declared or not): names and messages go
  // on into JSON reports and LCM strings, which must be valid text.
  const Utf8Error bad = find_invalid_utf8(text);
  if (bad.offset >= 0) {
    std::ostringstream msg;
    msg << path << ":" << bad.line << ": invalid UTF-8 at byte " << bad.offset << " (0x" << std::hex
        << static_cast<int>(static_cast<unsigned char>(text[static_cast<std::size_t>(bad.offset)])) << ")";
    throw InputError(msg.str());
  }
  if (text.find('\0') != std::string::npos) {
    const std::size_t at = text.find('\0');
    throw InputError(path + ":" + std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) +
                     ": a NUL byte at byte " + std::to_string(at) + " (not an XML text file)");
  }
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    std::ostringstream msg;
    msg << path << ":" << doc.ErrorLineNum() << ": " << doc.ErrorStr();
    throw InputError(msg.str());
  }
  // One document, one root: a second element after it would be ignored.
  if (const tinyxml2::XMLElement* root = doc.RootElement())
    if (const tinyxml2::XMLElement* extra = root->NextSiblingElement())
      fail_at(path, extra, std::string("a second top-level element after <") + root->Name() +
                               "> (a file holds one root element)");
}

bool parse_decimal_number(const char*& text, double& value) {
  // Decimal only: [+-]digits[.digits][(e|E)[+-]digits] after blanks.
  // strtod alone also takes hex ("0x10" as 16), "inf" and "nan".
  const char* p = text;
  while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
  const char* start = p;
  if (*p == '+' || *p == '-') ++p;
  const auto digits = [&p] {
    int n = 0;
    while (*p >= '0' && *p <= '9') ++p, ++n;
    return n;
  };
  int mantissa = digits();
  if (*p == '.') {
    ++p;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (*p == 'e' || *p == 'E') {
    ++p;
    if (*p == '+' || *p == '-') ++p;
    if (digits() == 0) return false;
  }
  const std::string token(start, p);
  value = std::strtod(token.c_str(), nullptr);
  if (!std::isfinite(value)) return false;
  text = p;
  return true;
}

namespace {
bool parse_number(const char*& text, double& value) { return parse_decimal_number(text, value); }
bool at_end(const char* p) {
  while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
  return *p == '\0';
}
}  // namespace

double AttributeReader::number(const char* name) {
  known_.insert(name);
  const char* text = e_->Attribute(name);
  if (!text) fail(std::string("missing attribute '") + name + "'");
  const char* p = text;
  double v = 0.0;
  if (!parse_number(p, v) || !at_end(p))
    fail(std::string("attribute '") + name + "' = \"" + text + "\": expected a number");
  return v;
}

void AttributeReader::check_range(const char* name, double v, double lo, double hi) const {
  if (!(v >= lo && v <= hi)) {
    std::ostringstream msg;
    msg << "attribute '" << name << "' = " << v << ": out of range [" << lo << ", " << hi << "]";
    fail(msg.str());
  }
}

double AttributeReader::number_in_or(const char* name, double lo, double hi, double fallback) {
  known_.insert(name);
  return e_->Attribute(name) ? number_in(name, lo, hi) : fallback;
}

double AttributeReader::number_in(const char* name, double lo, double hi) {
  const double v = number(name);
  check_range(name, v, lo, hi);
  return v;
}

Eigen::Vector3d AttributeReader::vector3_in(const char* name, double lo, double hi) {
  known_.insert(name);
  const char* text = e_->Attribute(name);
  if (!text) fail(std::string("missing attribute '") + name + "'");
  Eigen::Vector3d v;
  const char* p = text;
  for (int k = 0; k < 3; ++k)
    if (!parse_number(p, v[k])) fail(std::string("attribute '") + name + "' = \"" + text + "\": expected three numbers");
  if (!at_end(p)) fail(std::string("attribute '") + name + "' = \"" + text + "\": expected three numbers");
  for (int k = 0; k < 3; ++k) check_range(name, v[k], lo, hi);
  return v;
}

Eigen::VectorXd AttributeReader::numbers_in(const char* name, int count, double lo, double hi) {
  known_.insert(name);
  const char* text = e_->Attribute(name);
  if (!text) fail(std::string("missing attribute '") + name + "'");
  Eigen::VectorXd v(count);
  const char* p = text;
  for (int k = 0; k < count; ++k)
    if (!parse_number(p, v[k]))
      fail(std::string("attribute '") + name + "' = \"" + text + "\": expected " + std::to_string(count) + " numbers");
  if (!at_end(p))
    fail(std::string("attribute '") + name + "' = \"" + text + "\": expected " + std::to_string(count) + " numbers");
  for (int k = 0; k < count; ++k) check_range(name, v[k], lo, hi);
  return v;
}

bool AttributeReader::boolean_or(const char* name, bool fallback) {
  known_.insert(name);
  const char* t = e_->Attribute(name);
  if (!t) return fallback;
  const std::string s = t;
  if (s == "true" || s == "1") return true;
  if (s == "false" || s == "0") return false;
  fail(std::string("attribute '") + name + "' = \"" + s + "\": expected true or false");
}

std::string AttributeReader::text(const char* name, bool required) {
  known_.insert(name);
  const char* t = e_->Attribute(name);
  if (!t && required) fail(std::string("missing attribute '") + name + "'");
  return t ? t : "";
}

void AttributeReader::reject_content() const {
  for (const tinyxml2::XMLNode* n = e_->FirstChild(); n; n = n->NextSibling()) {
    if (const tinyxml2::XMLElement* c = n->ToElement())
      fail_at(path_, c, std::string("unexpected element inside <") + e_->Name() + "> (it takes no child elements)");
    if (const tinyxml2::XMLText* t = n->ToText()) {
      const std::string text = t->Value() ? t->Value() : "";
      if (text.find_first_not_of(" \t\r\n") != std::string::npos)
        fail(std::string("unexpected text \"") + text.substr(0, 40) + "\" (this element takes attributes only)");
    }
  }
}

void AttributeReader::reject_unknown() const {
  for (const tinyxml2::XMLAttribute* a = e_->FirstAttribute(); a; a = a->Next())
    if (!known_.count(a->Name())) fail(std::string("unknown attribute '") + a->Name() + "'");
}

}  // namespace skidsim::io
