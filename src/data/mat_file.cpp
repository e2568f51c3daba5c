#include "data/mat_file.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <optional>

#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"

namespace sets {

namespace {

// ------------------------------------------------------------------ bounded, byte-order aware view

class Bytes {
 public:
  // Messages read "<context>, <unit> <base + offset>: ...", e.g. "data.mat, byte 1234: ..." or
  // "data.mat: compressed variable at byte 128, inflated byte 56: ...".
  Bytes(std::string_view b, bool swap, std::string context, const char* unit = "byte", std::size_t base = 0)
      : b_(b), swap_(swap), context_(std::move(context)), unit_(unit), base_(base) {}

  /// The bytes [at, at + n) as a view of their own (offsets in messages stay those of the whole).
  Bytes part(std::size_t at, std::size_t n) const {
    need(at, n, "part");
    return Bytes(b_.substr(at, n), swap_, context_, unit_, base_ + at);
  }
  std::size_t size() const { return b_.size(); }
  bool swap() const { return swap_; }

  void need(std::size_t at, std::size_t n, const char* what) const {
    if (at > b_.size() || n > b_.size() - at)
      fail(at, std::string(what) + " needs " + std::to_string(n) + " bytes, only " +
                   std::to_string(at > b_.size() ? 0 : b_.size() - at) + " remain");
  }
  std::uint32_t u32(std::size_t at, const char* what) const {
    need(at, 4, what);
    std::uint32_t v;
    std::memcpy(&v, b_.data() + at, 4);
    return swap_ ? __builtin_bswap32(v) : v;
  }
  std::int32_t i32(std::size_t at, const char* what) const { return static_cast<std::int32_t>(u32(at, what)); }
  std::string_view view(std::size_t at, std::size_t n, const char* what) const {
    need(at, n, what);
    return b_.substr(at, n);
  }

  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw InputError(context_ + ", " + unit_ + " " + std::to_string(base_ + at) + ": " + what);
  }

 private:
  std::string_view b_;
  bool swap_;
  std::string context_;
  const char* unit_;
  std::size_t base_;
};

// Element value -> double for the numeric storage types (the byte order of the file).
template <class T>
double load(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if (swap) {
    char c[sizeof v];
    std::memcpy(c, &v, sizeof v);
    std::reverse(c, c + sizeof v);
    std::memcpy(&v, c, sizeof v);
  }
  return static_cast<double>(v);
}

// ------------------------------------------------------------------ level 5

enum : std::uint32_t {
  miINT8 = 1, miUINT8 = 2, miINT16 = 3, miUINT16 = 4, miINT32 = 5, miUINT32 = 6, miSINGLE = 7,
  miDOUBLE = 9, miINT64 = 12, miUINT64 = 13, miMATRIX = 14, miCOMPRESSED = 15
};

std::size_t mi_size(std::uint32_t type) {
  switch (type) {
    case miINT8: case miUINT8: return 1;
    case miINT16: case miUINT16: return 2;
    case miINT32: case miUINT32: case miSINGLE: return 4;
    case miDOUBLE: case miINT64: case miUINT64: return 8;
    default: return 0;
  }
}

double mi_value(std::uint32_t type, const char* p, bool swap) {
  switch (type) {
    case miINT8: return load<std::int8_t>(p, swap);
    case miUINT8: return load<std::uint8_t>(p, swap);
    case miINT16: return load<std::int16_t>(p, swap);
    case miUINT16: return load<std::uint16_t>(p, swap);
    case miINT32: return load<std::int32_t>(p, swap);
    case miUINT32: return load<std::uint32_t>(p, swap);
    case miSINGLE: return load<float>(p, swap);
    case miDOUBLE: return load<double>(p, swap);
    case miINT64: return load<std::int64_t>(p, swap);
    case miUINT64: return load<std::uint64_t>(p, swap);
    default: return 0;
  }
}

struct Element {
  std::uint32_t type = 0;
  std::size_t data = 0;  // offset of the data
  std::size_t size = 0;  // bytes of data
  std::size_t next = 0;  // offset of the following element (8-byte aligned)
};

// A data element at `at`: an 8-byte tag (type, bytes) or the small format (bytes in the upper
// half of the first word, at most 4 bytes of data in the second word).
Element element_at(const Bytes& b, std::size_t at, const char* what, bool data_present = true) {
  Element e;
  const std::uint32_t first = b.u32(at, what);
  if (first >> 16) {
    e.type = first & 0xFFFFu;
    e.size = first >> 16;
    if (e.size > 4) b.fail(at, std::string(what) + ": a small data element cannot hold " + std::to_string(e.size) + " bytes");
    e.data = at + 4;
    b.need(at, 8, what);
    e.next = at + 8;
    return e;
  }
  e.type = first;
  e.size = b.u32(at + 4, what);
  e.data = at + 8;
  if (data_present) b.need(e.data, e.size, what);
  const std::size_t padded = e.size + (8 - e.size % 8) % 8;
  e.next = std::min(e.data + padded, b.size());
  return e;
}

// The header of a miMATRIX element (array flags, dimensions, name) and whether the element is
// one that is read: a real numeric vector with more than one element and a name.
struct Matrix_header {
  bool wanted = false;
  std::size_t numel = 0;
  std::string name;
  std::size_t real_at = 0;  // offset of the real part
};

Matrix_header matrix_header(const Bytes& m) {
  Matrix_header h;
  if (m.size() == 0) return h;  // an empty matrix element
  const Element flags = element_at(m, 0, "array flags");
  if (flags.type != miUINT32 || flags.size != 8) m.fail(0, "the array flags of a matrix must be 8 bytes of miUINT32");
  const std::uint32_t word = m.u32(flags.data, "array flags");
  const std::uint32_t cls = word & 0xFFu;
  const bool complex = (word & 0x800u) != 0;

  const Element dims = element_at(m, flags.next, "dimensions");
  if (dims.type != miINT32 || dims.size < 8 || dims.size % 4 != 0)
    m.fail(flags.next, "the dimensions of a matrix must be at least two miINT32 values");
  const std::size_t rank = dims.size / 4;
  bool zero = false, huge = false;
  std::size_t numel = 1;
  for (std::size_t k = 0; k < rank; ++k) {
    const std::int32_t d = m.i32(dims.data + 4 * k, "dimensions");
    if (d < 0) m.fail(dims.data + 4 * k, "negative dimension " + std::to_string(d));
    zero = zero || d == 0;
    if (!huge) numel *= static_cast<std::size_t>(d);  // < 2^27 * 2^31: no overflow
    huge = huge || numel > max_mat_elements;
  }
  const bool vector_shape = rank == 2 && (m.i32(dims.data, "dimensions") == 1 || m.i32(dims.data + 4, "dimensions") == 1);

  const Element name = element_at(m, dims.next, "array name");
  if (name.type != miINT8 && name.type != miUINT8) m.fail(dims.next, "the name of a matrix must be miINT8 text");
  const std::string_view text = m.view(name.data, name.size, "array name");
  h.name = std::string(text.substr(0, text.find('\0')));
  h.real_at = name.next;
  h.numel = zero ? 0 : numel;
  h.wanted = cls >= 6 && cls <= 15 && !complex && vector_shape && !zero && numel > 1 && !h.name.empty();
  if (h.wanted && huge)
    m.fail(dims.data, "variable \"" + printable(h.name, 64) + "\" has more than " + std::to_string(max_mat_elements) +
                          " elements");
  return h;
}

// The values of a wanted matrix: its real part, whose size must match the dimensions.
std::vector<double> matrix_values(const Bytes& m, const Matrix_header& h) {
  const std::string quoted = "variable \"" + printable(h.name, 64) + "\"";
  const Element real = element_at(m, h.real_at, "real part");
  const std::size_t size = mi_size(real.type);
  if (size == 0) m.fail(h.real_at, quoted + ": the real part has data type " + std::to_string(real.type) + ", not a number");
  if (real.size != h.numel * size)
    m.fail(h.real_at, quoted + " has " + std::to_string(h.numel) + " elements but its real part holds " +
                          std::to_string(real.size) + " bytes of " + std::to_string(size) + "-byte values");
  std::vector<double> values(h.numel);
  const std::string_view data = m.view(real.data, real.size, "real part");
  for (std::size_t i = 0; i < h.numel; ++i) values[i] = mi_value(real.type, data.data() + i * size, m.swap());
  return values;
}

std::optional<Mat_vector> matrix_vector(const Bytes& m) {
  const Matrix_header h = matrix_header(m);
  if (!h.wanted) return std::nullopt;
  return Mat_vector{h.name, matrix_values(m, h)};
}

// Inflates a zlib stream into at most `limit` bytes; `complete` says whether the stream ended.
std::string inflate_at_most(std::string_view in, std::size_t limit, bool& complete, const Bytes& file, std::size_t at) {
  z_stream z{};
  if (inflateInit(&z) != Z_OK) throw InputError("zlib could not be initialised");
  std::string out;
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(std::min<std::size_t>(in.size(), 0xFFFFFFFFu));
  complete = false;
  int rc = Z_OK;
  while (out.size() < limit) {
    const std::size_t chunk = std::min<std::size_t>(limit - out.size(), std::size_t{1} << 16);
    const std::size_t before = out.size();
    out.resize(before + chunk);  // grows with the data really inflated, never to `limit` up front
    z.next_out = reinterpret_cast<Bytef*>(out.data() + before);
    z.avail_out = static_cast<uInt>(chunk);
    rc = inflate(&z, Z_NO_FLUSH);
    out.resize(before + (chunk - z.avail_out));
    if (rc == Z_STREAM_END) {
      complete = true;
      break;
    }
    if (rc != Z_OK) break;
    if (z.avail_out != 0 && z.avail_in == 0) break;  // the input ended inside the stream
  }
  inflateEnd(&z);
  if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR)
    file.fail(at, "compressed variable: " + std::string(z.msg ? printable(z.msg, 100) : "invalid zlib data"));
  return out;
}

std::optional<Mat_vector> compressed_vector(const Bytes& file, const Element& e, std::size_t at, const std::string& path) {
  const std::string_view stream = file.view(e.data, e.size, "compressed variable");
  const std::string context = path + ": compressed variable at byte " + std::to_string(at);
  // First the head of the element inside: its tag and, unless the name is very long, the matrix
  // header. Only a numeric vector is inflated in full, so a large variable that is skipped costs
  // nothing, and memory grows with the data really inflated, up to max_mat_variable_bytes.
  bool complete = false;
  const std::size_t head_size = std::size_t{1} << 16;
  std::string head = inflate_at_most(stream, head_size, complete, file, at);
  const Bytes head_bytes(head, file.swap(), context, "inflated byte");
  const Element m = element_at(head_bytes, 0, "compressed element", /*data_present=*/false);
  if (m.type != miMATRIX) return std::nullopt;
  if (m.size > max_mat_variable_bytes)
    head_bytes.fail(0, "the variable inflates to " + std::to_string(m.size) + " bytes, more than the limit of " +
                           std::to_string(max_mat_variable_bytes));
  const std::size_t total = 8 + m.size;
  if (head.size() < total) {
    if (head.size() == head_size) {  // the stream goes on: is the variable worth inflating?
      std::optional<Matrix_header> h;
      try {
        h = matrix_header(head_bytes.part(8, head.size() - 8));
      } catch (const InputError&) {
        // The header does not fit in the head (or is malformed, which the full read reports).
      }
      if (h && !h->wanted) return std::nullopt;
      head = inflate_at_most(stream, total, complete, file, at);
    }
    if (head.size() < total)
      Bytes(head, file.swap(), context, "inflated byte").fail(head.size(), "the compressed data end after " + std::to_string(head.size()) + " of " +
                                       std::to_string(total) + " bytes");
  }
  const Bytes inflated(head, file.swap(), context, "inflated byte");
  return matrix_vector(inflated.part(8, m.size));
}

// ------------------------------------------------------------------ level 4

struct V4_header {
  int precision = 0, text_or_sparse = 0;
  std::int32_t rows = 0, cols = 0, imag = 0, name_length = 0;
};

std::optional<V4_header> v4_header(const Bytes& b, std::size_t at) {
  V4_header h;
  const std::int32_t type = b.i32(at, "level 4 header");
  if (type < 0 || type > 1999 || (type / 100) % 10 != 0) return std::nullopt;  // IEEE only, O = 0
  if ((type / 1000 == 1) != b.swap()) return std::nullopt;                     // byte order as stated
  h.precision = (type / 10) % 10;
  h.text_or_sparse = type % 10;
  if (h.precision > 5 || h.text_or_sparse > 2) return std::nullopt;
  h.rows = b.i32(at + 4, "level 4 header");
  h.cols = b.i32(at + 8, "level 4 header");
  h.imag = b.i32(at + 12, "level 4 header");
  h.name_length = b.i32(at + 16, "level 4 header");
  if (h.rows < 0 || h.cols < 0 || (h.imag != 0 && h.imag != 1) || h.name_length < 1) return std::nullopt;
  return h;
}

}  // namespace

Mat_format mat_format(std::string_view bytes) {
  if (bytes.size() >= 128) {
    const unsigned char* p = reinterpret_cast<const unsigned char*>(bytes.data());
    unsigned version = 0;
    if (p[126] == 'I' && p[127] == 'M') version = p[124] | (p[125] << 8);
    else if (p[126] == 'M' && p[127] == 'I') version = (p[124] << 8) | p[125];
    if (version == 0x0100) return Mat_format::v5;
    if (version == 0x0200) return Mat_format::v73;
  }
  if (bytes.size() >= 20) return Mat_format::v4;  // confirmed or refuted by reading it
  return Mat_format::unknown;
}

std::vector<Mat_vector> read_mat_v5_vectors(std::string_view bytes, const std::string& path) {
  const bool swap = bytes.size() >= 128 && bytes[126] == 'M';  // "MI": written in the other byte order
  const Bytes file(bytes, swap, path);
  std::vector<Mat_vector> out;
  for (std::size_t at = 128; at < bytes.size();) {
    const Element e = element_at(file, at, "data element");
    std::optional<Mat_vector> v;
    if (e.type == miMATRIX) v = matrix_vector(file.part(e.data, e.size));
    else if (e.type == miCOMPRESSED) v = compressed_vector(file, e, at, path);
    if (v) out.push_back(std::move(*v));
    at = e.type == miCOMPRESSED ? e.data + e.size : e.next;  // compressed elements are not padded
  }
  return out;
}

std::vector<Mat_vector> read_mat_v4_vectors(std::string_view bytes, const std::string& path) {
  // The byte order is the one in which the first header makes sense.
  const bool swap = !v4_header(Bytes(bytes, false, path), 0);
  const Bytes file(bytes, swap, path);
  std::vector<Mat_vector> out;
  for (std::size_t at = 0; at < bytes.size();) {
    const auto h = v4_header(file, at);
    if (!h)
      file.fail(at, at == 0 ? "not a MATLAB .mat file (level 4, level 5 / v7, or v7.3)"
                            : "not a valid level 4 matrix header");
    const std::size_t name_at = at + 20;
    const std::string_view name_text = file.view(name_at, static_cast<std::size_t>(h->name_length), "variable name");
    const std::string var(name_text.substr(0, name_text.find('\0')));
    static const std::size_t sizes[] = {8, 4, 4, 2, 2, 1};
    const std::size_t size = sizes[h->precision];
    const std::size_t numel = static_cast<std::size_t>(h->rows) * static_cast<std::size_t>(h->cols);  // < 2^62
    const std::size_t data_at = name_at + static_cast<std::size_t>(h->name_length);
    const std::size_t remaining = data_at <= bytes.size() ? bytes.size() - data_at : 0;
    const std::size_t parts = h->imag ? 2 : 1;
    if (numel > remaining / size / parts)
      file.fail(at, "variable \"" + printable(var, 64) + "\" is " + std::to_string(h->rows) + " x " +
                        std::to_string(h->cols) + " but the file has only " + std::to_string(remaining) +
                        " bytes left");
    const bool wanted = h->text_or_sparse == 0 && !h->imag && (h->rows == 1 || h->cols == 1) && numel > 1 && !var.empty();
    if (wanted) {
      if (numel > max_mat_elements)
        file.fail(at, "variable \"" + printable(var, 64) + "\" has more than " + std::to_string(max_mat_elements) + " elements");
      Mat_vector v{var, std::vector<double>(numel)};
      const char* p = bytes.data() + data_at;
      for (std::size_t i = 0; i < numel; ++i, p += size) {
        switch (h->precision) {
          case 0: v.values[i] = load<double>(p, swap); break;
          case 1: v.values[i] = load<float>(p, swap); break;
          case 2: v.values[i] = load<std::int32_t>(p, swap); break;
          case 3: v.values[i] = load<std::int16_t>(p, swap); break;
          case 4: v.values[i] = load<std::uint16_t>(p, swap); break;
          default: v.values[i] = load<std::uint8_t>(p, swap); break;
        }
      }
      out.push_back(std::move(v));
    }
    at = data_at + numel * size * parts;
  }
  return out;
}

}  // namespace sets
