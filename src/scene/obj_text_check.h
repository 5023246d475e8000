// A strict pass over OBJ text before tinyobjloader parses it. tinyobjloader reads
// "nan", "inf" and any unparsable number as 0, fills a missing coordinate with 0,
// resolves face indices without a bounds check and stores a face's corner count in an
// unsigned char; each of those would be a silently wrong scene. This pass refuses them.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace lancer::obj_detail {

struct ObjTextSummary {
  std::size_t unknown_statements = 0;    // lines with a keyword OBJ does not define
  std::size_t first_unknown_line = 0;    // 1-based line number of the first of them
  std::size_t lines_and_points = 0;      // `l` and `p` statements (not triangles)
};

// Throws SceneError(file, "line N: ...") on a malformed v/vn/vt/f/l/p statement or a
// vertex, normal or texcoord index outside the file's arrays. Lines are split as
// tinyobjloader splits them (\n, \r or \r\n), so line numbers agree with its messages.
ObjTextSummary check_obj_text(std::string_view text, const std::string& file);

}  // namespace lancer::obj_detail
