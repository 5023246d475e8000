#include "scene/obj_text_check.h"

#include <charconv>
#include <climits>
#include <cmath>
#include <system_error>
#include <vector>

#include "scene/scene_error.h"

namespace lancer::obj_detail {

namespace {

// Statements of the OBJ specification (Wavefront, Appendix B1) that this pass does not
// check but tinyobjloader handles or ignores, plus tinyobjloader's `t` (subdivision tags).
constexpr std::string_view kOtherKeywords[] = {
    "vp",   "vw",    "o",    "g",     "s",     "mg",       "mtllib",   "usemtl", "cstype", "deg",    "bmat",
    "step", "curv",  "curv2", "surf", "parm",  "trim",     "hole",     "scrv",   "sp",     "end",    "con",
    "bevel", "c_interp", "d_interp", "lod", "usemap", "maplib", "shadow_obj", "trace_obj", "ctech", "stech",
    "call", "csh",   "t"};

enum class Attribute { Position = 0, Texcoord = 1, Normal = 2 };
constexpr const char* kAttributeNames[3] = {"vertex", "texcoord", "normal"};
constexpr const char* kAttributePlurals[3] = {"vertices", "texcoords", "normals"};

enum class NumberStatus { Ok, NotANumber, NonFinite };

// Parses a whole token as a number that fits a finite float. std::from_chars is
// locale-independent; it takes no leading '+', which OBJ writers sometimes emit.
NumberStatus parse_coordinate(std::string_view s) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ptr != s.data() + s.size() || s.empty()) return NumberStatus::NotANumber;
  if (ec == std::errc::result_out_of_range) {
    // Underflow (a negative exponent) reads as 0, as every OBJ reader does; overflow is infinite.
    const auto e = s.find_first_of("eE");
    const bool underflow = e != std::string_view::npos && e + 1 < s.size() && s[e + 1] == '-';
    return underflow ? NumberStatus::Ok : NumberStatus::NonFinite;
  }
  if (ec != std::errc()) return NumberStatus::NotANumber;
  return std::isfinite(static_cast<float>(value)) ? NumberStatus::Ok : NumberStatus::NonFinite;
}

class Checker {
 public:
  explicit Checker(const std::string& file) : file_(file) {}

  ObjTextSummary run(std::string_view text) {
    std::size_t pos = 0;
    while (pos < text.size()) {
      // Split exactly as tinyobjloader's safeGetline: "\n", "\r" or "\r\n" ends a line.
      std::size_t end = text.find_first_of("\r\n", pos);
      if (end == std::string_view::npos) end = text.size();
      ++line_;
      check_line(text.substr(pos, end - pos));
      pos = end;
      if (pos < text.size() && text[pos++] == '\r' && pos < text.size() && text[pos] == '\n') ++pos;
    }
    for (int a = 0; a < 3; ++a)
      if (max_positive_[a] > count_[a])
        throw SceneError(file_, "line " + std::to_string(max_positive_line_[a]) + ": " + kAttributeNames[a] +
                                    " index " + std::to_string(max_positive_[a]) + " is out of range (the file has " +
                                    std::to_string(count_[a]) + " " + kAttributePlurals[a] + ")");
    return summary_;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw SceneError(file_, "line " + std::to_string(line_) + ": " + what);
  }

  void check_line(std::string_view line) {
    tokens_.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
      if (j > i) {
        if (line[i] == '#') break;  // a comment runs to the end of the line
        tokens_.push_back(line.substr(i, j - i));
      }
      i = j;
    }
    if (tokens_.empty()) return;
    const std::string_view keyword = tokens_[0];
    if (keyword == "v") {
      check_numbers(3, 7, "vertex position");  // x y z [w] or x y z r g b [w]
      ++count_[static_cast<int>(Attribute::Position)];
    } else if (keyword == "vn") {
      check_numbers(3, 3, "normal");
      ++count_[static_cast<int>(Attribute::Normal)];
    } else if (keyword == "vt") {
      check_numbers(1, 3, "texcoord");
      ++count_[static_cast<int>(Attribute::Texcoord)];
    } else if (keyword == "f") {
      const std::size_t corners = tokens_.size() - 1;
      if (corners < 3) fail("face with " + std::to_string(corners) + " vertices (needs at least 3)");
      // tinyobjloader keeps a face's corner count in an unsigned char.
      if (corners > 255) fail("face with " + std::to_string(corners) + " vertices (at most 255 are supported)");
      for (std::size_t k = 1; k < tokens_.size(); ++k) check_corner(tokens_[k]);
    } else if (keyword == "l" || keyword == "p") {
      for (std::size_t k = 1; k < tokens_.size(); ++k) check_corner(tokens_[k]);
      ++summary_.lines_and_points;
    } else if (!known_keyword(keyword)) {
      if (summary_.unknown_statements++ == 0) summary_.first_unknown_line = line_;
    }
  }

  static bool known_keyword(std::string_view keyword) {
    for (std::string_view k : kOtherKeywords)
      if (k == keyword) return true;
    return false;
  }

  void check_numbers(std::size_t min_count, std::size_t max_count, const char* what) {
    const std::size_t n = tokens_.size() - 1;
    if (n < min_count || n > max_count)
      fail(std::string(what) + " with " + std::to_string(n) + " numbers (expected " +
           (min_count == max_count ? std::to_string(min_count)
                                   : std::to_string(min_count) + " to " + std::to_string(max_count)) +
           ")");
    for (std::size_t k = 1; k < tokens_.size(); ++k) {
      const NumberStatus status = parse_coordinate(tokens_[k]);
      if (status == NumberStatus::NotANumber) fail(std::string(what) + ": '" + std::string(tokens_[k]) + "' is not a number");
      if (status == NumberStatus::NonFinite)
        fail(std::string(what) + ": '" + std::string(tokens_[k]) + "' is not finite (NaN, Inf or out of float range)");
    }
  }

  // A corner is v, v/t, v//n or v/t/n.
  void check_corner(std::string_view corner) {
    std::string_view parts[3];
    int count = 0;
    std::size_t start = 0;
    while (true) {
      const std::size_t slash = corner.find('/', start);
      if (count == 3) fail("face corner '" + std::string(corner) + "' has more than three indices");
      parts[count++] = corner.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
      if (slash == std::string_view::npos) break;
      start = slash + 1;
    }
    check_index(parts[0], Attribute::Position, corner);
    if (count >= 2 && !(count == 3 && parts[1].empty())) check_index(parts[1], Attribute::Texcoord, corner);
    if (count == 3) check_index(parts[2], Attribute::Normal, corner);
  }

  void check_index(std::string_view digits, Attribute attribute, std::string_view corner) {
    const int a = static_cast<int>(attribute);
    const std::string name = kAttributeNames[a];
    if (digits.size() > 1 && digits[0] == '+') digits.remove_prefix(1);
    long long index = 0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
    if (digits.empty() || ec != std::errc() || ptr != digits.data() + digits.size())
      fail("face corner '" + std::string(corner) + "': " + name + " index '" + std::string(digits) + "' is not an integer");
    if (index == 0) fail("face corner '" + std::string(corner) + "': " + name + " index 0 (OBJ indices start at 1)");
    if (index > INT_MAX || index < -static_cast<long long>(INT_MAX))
      fail("face corner '" + std::string(corner) + "': " + name + " index " + std::to_string(index) + " is out of range");
    if (index < 0) {
      // Relative: -1 is the latest element defined above this line.
      if (static_cast<long long>(count_[a]) + index < 0)
        fail("face corner '" + std::string(corner) + "': relative " + name + " index " + std::to_string(index) +
             " is out of range (" + std::to_string(count_[a]) + " " + kAttributePlurals[a] + " defined so far)");
    } else if (static_cast<std::size_t>(index) > max_positive_[a]) {
      // Checked at the end: a face may name a vertex defined further down.
      max_positive_[a] = static_cast<std::size_t>(index);
      max_positive_line_[a] = line_;
    }
  }

  const std::string& file_;
  std::size_t line_ = 0;
  std::vector<std::string_view> tokens_;
  std::size_t count_[3] = {0, 0, 0};
  std::size_t max_positive_[3] = {0, 0, 0};
  std::size_t max_positive_line_[3] = {0, 0, 0};
  ObjTextSummary summary_;
};

}  // namespace

ObjTextSummary check_obj_text(std::string_view text, const std::string& file) { return Checker(file).run(text); }

}  // namespace lancer::obj_detail
