// PLY reader (ASCII, binary little and big endian, any element/property layout); the writer is in
// mesh/io_ply_write.cpp.
//
// The reader walks every element of the header in order, so elements other than vertex, face and tristrips
// (triangle strips, as some scanners write them; -1 ends a strip) (edges, materials, ...) are read and
// dropped, and any property layout works. Counts are checked against the bytes left before anything is
// allocated.
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io_formats.h"

namespace cshapes::io_detail {

namespace {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

bool parse_type(std::string_view name, PlyType& type) {
  static const struct {
    const char* name;
    const char* alias;
    PlyType type;
  } types[] = {{"char", "int8", PlyType::int8},        {"uchar", "uint8", PlyType::uint8},
               {"short", "int16", PlyType::int16},     {"ushort", "uint16", PlyType::uint16},
               {"int", "int32", PlyType::int32},       {"uint", "uint32", PlyType::uint32},
               {"float", "float32", PlyType::float32}, {"double", "float64", PlyType::float64}};
  for (const auto& t : types)
    if (name == t.name || name == t.alias) {
      type = t.type;
      return true;
    }
  return false;
}

size_t type_size(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8:
      return 1;
    case PlyType::int16:
    case PlyType::uint16:
      return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32:
      return 4;
    case PlyType::float64:
      return 8;
  }
  return 1;
}

long long integer_min(PlyType type) {
  switch (type) {
    case PlyType::int8:
      return INT8_MIN;
    case PlyType::int16:
      return INT16_MIN;
    case PlyType::int32:
      return INT32_MIN;
    default:
      return 0;
  }
}

long long integer_max(PlyType type) {
  switch (type) {
    case PlyType::int8:
      return INT8_MAX;
    case PlyType::uint8:
      return UINT8_MAX;
    case PlyType::int16:
      return INT16_MAX;
    case PlyType::uint16:
      return UINT16_MAX;
    case PlyType::int32:
      return INT32_MAX;
    default:
      return UINT32_MAX;
  }
}

// Names become parts of error messages and of written headers: printable, no spaces.
std::string plain_name(TextScanner& scanner, std::string_view name) {
  for (unsigned char c : name)
    if (c <= 32 || c >= 127) fail(scanner.where(), ": '", printable(name), "' is not a valid PLY name");
  return std::string(name);
}

bool is_integer_type(PlyType type) {
  return type != PlyType::float32 && type != PlyType::float64;
}

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::uint8;  // lists only
  PlyType type = PlyType::float32;      // the value (or the list items)
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
  int header_line = 0;
};

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

bool host_is_little_endian() {
  const uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

// Reads the values of the data section one by one, as text tokens or as binary numbers.
class PlyValueReader {
 public:
  PlyValueReader(const std::string& name, std::string_view bytes, size_t start, int line, PlyFormat format)
      : name_(name),
        bytes_(bytes),
        format_(format),
        data_start_(start),
        pos_(start),
        scanner_(name, bytes, false, start, line),
        swap_(format != PlyFormat::ascii &&
              (format == PlyFormat::binary_little_endian) != host_is_little_endian()) {}

  bool ascii() const { return format_ == PlyFormat::ascii; }
  size_t remaining_bytes() const { return ascii() ? scanner_.remaining_bytes() : bytes_.size() - pos_; }
  // Where the current element is: "NAME:LINE: face 12" (ASCII) or "NAME: face 12" (binary).
  std::string where(const std::string& element, long long index) const {
    return ascii() ? detail::concat(scanner_.where(), ": ", element, " ", index)
                   : detail::concat(name_, ": ", element, " ", index);
  }

  double value(PlyType type, const std::string& element, long long index, const std::string& property) {
    if (ascii()) {
      std::string_view t;
      if (!scanner_.next(t))
        fail(where(element, index), ": unexpected end of file (truncated?), expected property '", property,
             "'", counts_note());
      if (is_integer_type(type)) {
        long long v = 0;
        if (!parse_integer(t, v) || v < integer_min(type) || v > integer_max(type))
          fail(where(element, index), ": expected an integer of the property's type for '", property,
               "', found '", printable(t), "'");
        return static_cast<double>(v);
      }
      double v = 0;
      if (!parse_real(t, v))
        fail(where(element, index), ": expected a number for property '", property, "', found '",
             printable(t), "'");
      return v;
    }
    size_t size = type_size(type);
    if (bytes_.size() - pos_ < size)
      fail(where(element, index), ": unexpected end of file (truncated?) in property '", property, "'",
           counts_note());
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + pos_, size);
    pos_ += size;
    if (swap_)
      for (size_t k = 0; k < size / 2; ++k) std::swap(raw[k], raw[size - 1 - k]);
    switch (type) {
      case PlyType::int8:
        return static_cast<int8_t>(raw[0]);
      case PlyType::uint8:
        return raw[0];
      case PlyType::int16:
        return load<int16_t>(raw);
      case PlyType::uint16:
        return load<uint16_t>(raw);
      case PlyType::int32:
        return load<int32_t>(raw);
      case PlyType::uint32:
        return load<uint32_t>(raw);
      case PlyType::float32:
        return load<float>(raw);
      case PlyType::float64:
        return load<double>(raw);
    }
    return 0;
  }

  // What the header claims, for messages about a file that ends early: "; the header claims 500 vertex and
  // 1000 face items, the data section holds 1200 lines" (ASCII: one item per line) or "... N bytes" (binary).
  void set_claimed(std::string claimed) { claimed_ = std::move(claimed); }
  std::string counts_note() const {
    if (claimed_.empty()) return "";
    if (!ascii()) return detail::concat("; the header claims ", claimed_, ", the data section holds ",
                                        bytes_.size() - data_start_, " bytes");
    long long lines = 0;
    for (size_t k = data_start_, start = k; k <= bytes_.size(); ++k)
      if (k == bytes_.size() || bytes_[k] == '\n') {
        lines += bytes_.substr(start, k - start).find_first_not_of(" \t\r") != std::string_view::npos;
        start = k + 1;
      }
    return detail::concat("; the header claims ", claimed_, ", the data section holds ", lines,
                          " non-empty lines (one item per line)");
  }

  // After the last element: nothing but whitespace (ASCII) or nothing at all (binary) may remain.
  void expect_end() {
    if (ascii()) {
      std::string_view t;
      if (scanner_.next(t))
        fail(scanner_.where(), ": unexpected data '", printable(t),
             "' after the last element (count mismatch)");
    } else if (pos_ != bytes_.size()) {
      fail(name_, ": ", bytes_.size() - pos_, " bytes after the last element (count mismatch)");
    }
  }

 private:
  template <typename T>
  static double load(const unsigned char* raw) {
    T v;
    std::memcpy(&v, raw, sizeof v);
    return static_cast<double>(v);
  }

  const std::string& name_;
  std::string_view bytes_;
  PlyFormat format_;
  size_t data_start_ = 0;
  size_t pos_;
  std::string claimed_;
  TextScanner scanner_;
  bool swap_;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  size_t data_start = 0;
  int data_line = 1;
  std::vector<std::string> comments;  // the text of each "comment" line
};

PlyHeader parse_header(const std::string& name, std::string_view bytes) {
  if (bytes.substr(0, 3) != "ply" || (bytes.size() > 3 && bytes[3] != '\n' && bytes[3] != '\r'))
    fail(name, ":1: not a PLY file (expected 'ply' on the first line)");
  TextScanner scanner(name, bytes, false, 3, 1);
  PlyHeader header;
  bool have_format = false;
  std::string_view t;
  for (;;) {
    std::string_view keyword = scanner.token("'end_header' (truncated header?)");
    if (keyword == "end_header") {
      scanner.skip_line();
      // The data starts right after the header's last newline (binary data may begin with any byte).
      header.data_start = std::min(scanner.position() + 1, bytes.size());
      header.data_line = scanner.line() + 1;
      break;
    }
    if (keyword == "comment" || keyword == "obj_info") {
      if (keyword == "comment") {
        const size_t start = std::min(scanner.position(), bytes.size());
        std::string_view text = bytes.substr(start, bytes.find_first_of("\r\n", start) - start);
        while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
        while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
        header.comments.emplace_back(text);
      }
      scanner.skip_line();
    } else if (keyword == "format") {
      std::string_view kind = scanner.token_on_line("ascii, binary_little_endian or binary_big_endian");
      if (kind == "ascii")
        header.format = PlyFormat::ascii;
      else if (kind == "binary_little_endian")
        header.format = PlyFormat::binary_little_endian;
      else if (kind == "binary_big_endian")
        header.format = PlyFormat::binary_big_endian;
      else
        fail(scanner.where(), ": unknown PLY format '", printable(kind), "'");
      scanner.token_on_line("the format version");
      have_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      element.name = plain_name(scanner, scanner.token_on_line("an element name"));
      element.count = scanner.integer_on_line("the element count");
      element.header_line = scanner.line();
      if (element.count < 0)
        fail(scanner.where(), ": negative count for element '", printable(element.name), "'");
      header.elements.push_back(element);
    } else if (keyword == "property") {
      if (header.elements.empty()) fail(scanner.where(), ": property before any element");
      PlyProperty property;
      std::string_view type = scanner.token_on_line("a property type");
      if (type == "list") {
        property.is_list = true;
        std::string_view count_type = scanner.token_on_line("the list's count type");
        if (!parse_type(count_type, property.count_type) || !is_integer_type(property.count_type))
          fail(scanner.where(), ": expected an integer type for the list count, found '",
               printable(count_type), "'");
        type = scanner.token_on_line("the list's item type");
      }
      if (!parse_type(type, property.type))
        fail(scanner.where(), ": unknown property type '", printable(type), "'");
      property.name = plain_name(scanner, scanner.token_on_line("a property name"));
      for (const PlyProperty& earlier : header.elements.back().properties)
        if (earlier.name == property.name)
          fail(scanner.where(), ": property '", printable(property.name), "' appears twice in element '",
               printable(header.elements.back().name), "' (expected distinct property names)");
      header.elements.back().properties.push_back(property);
    } else {
      fail(scanner.where(), ": unexpected '", printable(keyword), "' in the PLY header");
    }
    if (scanner.next_on_line(t))
      fail(scanner.where(), ": unexpected '", printable(t), "' at the end of the line");
  }
  if (!have_format) fail(name, ": PLY header has no 'format' line");
  return header;
}

int find_property(const PlyElement& element, const char* name, bool list) {
  for (size_t k = 0; k < element.properties.size(); ++k)
    if (element.properties[k].name == name && element.properties[k].is_list == list)
      return static_cast<int>(k);
  return -1;
}

// One list of a 'tristrips' element: strips of vertex indices separated by -1; in a strip v0 v1 v2 v3 ...
// triangle k is (v_k, v_k+1, v_k+2), every second one reversed so that all keep the strip's orientation.
// Triangles with a repeated corner (the joins some writers use instead of -1) are left out.
void read_triangle_strips(PlyValueReader& reader, const std::string& element, long long item,
                          const PlyProperty& p, long long count, long long vertex_limit,
                          MeshBuilder& builder) {
  std::vector<int> strip;
  auto flush = [&] {
    for (size_t k = 0; k + 2 < strip.size(); ++k) {
      const int a = strip[k], b = strip[k + 1], c = strip[k + 2];
      if (a == b || b == c || a == c) continue;
      if (k % 2 == 0)
        builder.triangles.insert(builder.triangles.end(), {a, b, c});
      else
        builder.triangles.insert(builder.triangles.end(), {b, a, c});
    }
    strip.clear();
  };
  for (long long j = 0; j < count; ++j) {
    const double index = reader.value(p.type, element, item, p.name);
    if (index == -1) {
      flush();
      continue;
    }
    if (!(index >= 0 && index < static_cast<double>(vertex_limit) && index == std::floor(index)))
      fail(reader.where(element, item), " has vertex index ", index, ", expected -1 (a strip's end) or 0..",
           vertex_limit - 1);
    strip.push_back(static_cast<int>(index));
  }
  flush();
}

}  // namespace

namespace {

// Which properties of an element the reader takes (−1: none): a vertex's coordinates, 8-bit colours, its
// "valid" flag and other scalars (slot in file.scalars per property); a face's or strip's index list.
struct ElementSlots {
  int x = -1, y = -1, z = -1, red = -1, green = -1, blue = -1, indices = -1, valid = -1;
  std::vector<int> scalar_slot;  // property → index in file.scalars, or −1
};

// The slots of `element`; for the vertex element also the room for its colours and scalars in `file`.
ElementSlots element_slots(const std::string& name, const PlyElement& element, MeshFile& file,
                           MeshBuilder& builder) {
  ElementSlots s;
  s.scalar_slot.assign(element.properties.size(), -1);
  if (element.name == "vertex") {
    s.x = find_property(element, "x", false);
    s.y = find_property(element, "y", false);
    s.z = find_property(element, "z", false);
    if (s.x < 0 || s.y < 0 || s.z < 0)
      fail(name, ":", element.header_line, ": the vertex element has no x, y, z properties");
    s.red = find_property(element, "red", false);
    s.green = find_property(element, "green", false);
    s.blue = find_property(element, "blue", false);
    bool colors = s.red >= 0 && s.green >= 0 && s.blue >= 0 &&
                  element.properties[s.red].type == PlyType::uint8 &&
                  element.properties[s.green].type == PlyType::uint8 &&
                  element.properties[s.blue].type == PlyType::uint8;
    if (!colors)
      s.red = s.green = s.blue = -1;
    else
      file.colors.resize(element.count, 3);
    for (size_t k = 0; k < element.properties.size(); ++k) {
      const PlyProperty& p = element.properties[k];
      int kk = static_cast<int>(k);
      if (p.is_list || kk == s.x || kk == s.y || kk == s.z || kk == s.red || kk == s.green || kk == s.blue)
        continue;
      s.scalar_slot[k] = static_cast<int>(file.scalars.size());
      file.scalars.push_back({p.name, Eigen::VectorXd(element.count)});
    }
    builder.coords.reserve(3 * element.count);
    // A vertex row may hold NaN/Inf coordinates only when its "valid" property is 0 (a canonical form's
    // dropped vertex, as write_mesh writes it); the check waits for the row's end, where valid is known.
    s.valid = find_property(element, "valid", false);
  } else if (element.name == "face") {
    s.indices = find_property(element, "vertex_indices", true);
    if (s.indices < 0) s.indices = find_property(element, "vertex_index", true);
    if (s.indices < 0 && element.count > 0)
      fail(name, ":", element.header_line, ": the face element has no 'vertex_indices' list property");
  } else if (element.name == "tristrips") {  // triangle strips, -1 between strips
    s.indices = find_property(element, "vertex_indices", true);
    if (s.indices < 0 && element.count > 0)
      fail(name, ":", element.header_line, ": the tristrips element has no 'vertex_indices' list property");
  }
  return s;
}

// Checks that `element` fits in what is left of the file: its smallest possible size is a token (at least 2
// bytes with its separator) per property in ASCII, the scalar and list-count sizes in binary. Returns that
// size (0: no properties, no data).
size_t check_element_size(const std::string& name, const PlyElement& element, const PlyValueReader& reader) {
  size_t min_size = 0;
  for (const PlyProperty& p : element.properties)
    min_size += reader.ascii() ? 1 : type_size(p.is_list ? p.count_type : p.type);
  if (min_size > 0 && static_cast<unsigned long long>(element.count) > (reader.remaining_bytes() + 1) / min_size)
    fail(name, ":", element.header_line, ": element '", printable(element.name), "' declares ", element.count,
         " items, more than the remaining ", reader.remaining_bytes(),
         " bytes can hold (truncated file or wrong count)");
  if (element.count > INT_MAX)
    fail(name, ":", element.header_line, ": too many items in element '", printable(element.name), "'");
  return min_size;
}

// One face's list of n vertex indices, each checked against the vertex count when the vertices came first.
void read_polygon(PlyValueReader& reader, const std::string& element, long long item, const PlyProperty& p,
                  long long n, bool have_vertices, long long nv, std::vector<int>& polygon,
                  MeshBuilder& builder) {
  if (n < 3) fail(reader.where(element, item), " has ", n, " vertex indices, expected at least 3");
  polygon.clear();
  for (long long j = 0; j < n; ++j) {
    double index = reader.value(p.type, element, item, p.name);
    // A vertex element after the face element is legal; its indices are then checked after loading.
    double limit = have_vertices ? static_cast<double>(nv) : static_cast<double>(INT_MAX);
    if (!(index >= 0 && index < limit && index == std::floor(index)))
      fail(reader.where(element, item), " has vertex index ", index, ", expected 0..", nv - 1);
    polygon.push_back(static_cast<int>(index));
  }
  builder.add_polygon(polygon);
}

}  // namespace

MeshFile parse_ply(const std::string& name, std::string_view bytes) {
  PlyHeader header = parse_header(name, bytes);
  PlyValueReader reader(name, bytes, header.data_start, header.data_line, header.format);
  std::string claimed;
  for (const PlyElement& element : header.elements) {
    if (!claimed.empty()) claimed += " and ";
    claimed += std::to_string(element.count) + " " + printable(element.name);
  }
  reader.set_claimed(claimed + (header.elements.size() == 1 ? " item" : " items"));
  // Binary: the smallest data the header's counts need (a face at least a triangle) against what is there,
  // so that a count larger than the data is named as such, not as a damaged face further on.
  long double needed = 0;
  for (const PlyElement& element : header.elements)
    for (const PlyProperty& p : element.properties) {
      const bool face_list = element.name == "face" && p.is_list && p.name.rfind("vertex_ind", 0) == 0;
      needed += element.count * (p.is_list ? type_size(p.count_type) + (face_list ? 3.0L * type_size(p.type) : 0)
                                           : static_cast<long double>(type_size(p.type)));
    }
  if (!reader.ascii() && needed > static_cast<long double>(reader.remaining_bytes()))
    fail(name, ": the header claims ", claimed, " items, at least ",
         needed < 1e18L ? std::to_string(static_cast<unsigned long long>(needed)) : "1e18", " bytes of data; the file "
         "holds ", reader.remaining_bytes(), " after its header (truncated or wrong counts)");
  MeshFile file;
  file.comments = header.comments;
  MeshBuilder builder;
  bool have_vertices = false;
  long long nv = 0;
  std::vector<int> polygon;
  for (const PlyElement& element : header.elements) {
    const size_t min_size = check_element_size(name, element, reader);
    const bool is_vertex = element.name == "vertex";
    const bool is_strips = element.name == "tristrips";
    if (is_vertex) {
      if (have_vertices) fail(name, ":", element.header_line, ": a second 'vertex' element");
      have_vertices = true;
      nv = element.count;
    }
    const ElementSlots s = element_slots(name, element, file, builder);
    if (min_size == 0) continue;
    for (long long i = 0; i < element.count; ++i) {
      double xyz[3] = {0, 0, 0};
      const char* non_finite = nullptr;  // the first non-finite coordinate's name
      double valid_value = 1;
      for (size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& p = element.properties[k];
        const int kk = static_cast<int>(k);
        if (!p.is_list) {
          double v = reader.value(p.type, element.name, i, p.name);
          if (kk == s.valid) valid_value = v;
          if (kk == s.x || kk == s.y || kk == s.z) {
            if (!std::isfinite(v) && !non_finite) non_finite = p.name.c_str();
            xyz[kk == s.x ? 0 : kk == s.y ? 1 : 2] = v;
          } else if (kk == s.red || kk == s.green || kk == s.blue) {
            file.colors(i, kk == s.red ? 0 : kk == s.green ? 1 : 2) = static_cast<unsigned char>(v);
          } else if (s.scalar_slot[k] >= 0) {
            file.scalars[s.scalar_slot[k]].values[i] = v;
          }
          continue;
        }
        double count = reader.value(p.count_type, element.name, i, p.name);
        const size_t item_size = reader.ascii() ? 2 : type_size(p.type);
        if (count < 0 || count > static_cast<double>(reader.remaining_bytes() / item_size + 1))
          fail(reader.where(element.name, i), ": list '", p.name, "' declares ", count,
               " items, more than the rest of the file holds (truncated?)");
        const long long n = static_cast<long long>(count);
        if (kk != s.indices) {
          for (long long j = 0; j < n; ++j) reader.value(p.type, element.name, i, p.name);
        } else if (is_strips) {
          read_triangle_strips(reader, element.name, i, p, n, have_vertices ? nv : INT_MAX, builder);
        } else {
          read_polygon(reader, element.name, i, p, n, have_vertices, nv, polygon, builder);
        }
      }
      if (non_finite && valid_value != 0)
        fail(reader.where(element.name, i), " has a non-finite ", non_finite, " coordinate (NaN or Inf)",
             s.valid >= 0 ? "" : " and no 'valid' property = 0 marking it");
      if (is_vertex) builder.add_vertex(xyz[0], xyz[1], xyz[2]);
    }
  }
  reader.expect_end();
  if (!have_vertices) fail(name, ": PLY file has no 'vertex' element");
  file.mesh = builder.mesh();
  return file;
}

}  // namespace cshapes::io_detail
