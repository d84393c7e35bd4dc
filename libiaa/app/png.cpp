// PNG writing (our own encoder over zlib, compressing the rows in parts in parallel) and reading
// (libpng). Application layer: used by tools/ and viz/, never by the library modules.
#include "app/png.h"

#include <png.h>
#include <tbb/parallel_for.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "app/files.h"
#include "core/error.h"

namespace iaa::app {

namespace {

/// Filtered bytes per independently compressed part of the image data (whole rows, at least
/// one): about 6 parts for a 500x500 RGB image. A fixed size, not one per thread, so that the
/// file's bytes depend on the pixels alone.
constexpr std::size_t kPartBytes = std::size_t(1) << 17;

/// The longest row written (bytes): a part holds whole rows, and one row's data, compressed, must
/// fit zlib's 32-bit counts and a PNG chunk (at most 2^31 - 1 bytes).
constexpr std::size_t kMaxRowBytes = std::size_t(1) << 30;

/// Appends v big-endian (PNG's byte order) to a string or a byte vector.
template <class Bytes>
void put_u32(Bytes& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) {
    out.push_back(static_cast<typename Bytes::value_type>(v >> shift));
  }
}

/// Appends a PNG chunk: length, type, data, CRC-32 of type and data.
void put_chunk(std::string& out, const char (&type)[5], const std::vector<std::uint8_t>& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t at = out.size();
  out.append(type, 4);
  out.append(data.begin(), data.end());
  const uLong crc = crc32_z(crc32(0L, nullptr, 0), reinterpret_cast<const Bytef*>(out.data() + at),
                            4 + data.size());
  put_u32(out, static_cast<std::uint32_t>(crc));
}

/// Rows [y0, y1) with PNG's Sub filter (type 1: each byte minus the byte one pixel to its left),
/// which on rendered images (flat backgrounds, smooth shading) compresses as well as libpng's
/// adaptive choice among the five filters, in less time.
std::vector<std::uint8_t> filtered_rows(const Image8& image, int y0, int y1) {
  const std::size_t row = std::size_t(image.width) * image.channels;
  const int bpp = image.channels;
  std::vector<std::uint8_t> out((row + 1) * std::size_t(y1 - y0));
  std::uint8_t* o = out.data();
  for (int y = y0; y < y1; ++y) {
    const std::uint8_t* in = image.at(0, y);
    *o++ = 1;
    for (int i = 0; i < bpp; ++i) *o++ = in[i];
    for (std::size_t i = static_cast<std::size_t>(bpp); i < row; ++i) {
      *o++ = static_cast<std::uint8_t>(in[i] - in[i - static_cast<std::size_t>(bpp)]);
    }
  }
  return out;
}

/// One part of the zlib stream: raw deflate of the part's filtered rows, ended by a sync flush
/// (byte-aligned, so that parts concatenate into one stream) or, for the last part, by the final
/// block; and the part's Adler-32 and length for the stream's checksum.
struct Part {
  std::vector<std::uint8_t> deflated;
  uLong adler = 0;
  std::size_t size = 0;
  bool ok = false;
};

/// A deflate stream, ended on every path out (exceptions included).
struct Deflater {
  z_stream zs{};
  bool open = false;
  // Level 6 (zlib's default), raw deflate (no zlib header: the parts share the stream's).
  Deflater() { open = deflateInit2(&zs, 6, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) == Z_OK; }
  ~Deflater() {
    if (open) deflateEnd(&zs);
  }
  Deflater(const Deflater&) = delete;
  Deflater& operator=(const Deflater&) = delete;
};

Part deflate_part(const std::vector<std::uint8_t>& in, bool last) {
  Part p;
  p.size = in.size();  // at most a part or one row: both under kMaxRowBytes + 1, in a uInt
  p.adler = adler32_z(adler32(0L, nullptr, 0), in.data(), in.size());
  Deflater d;
  if (!d.open) return p;
  d.zs.next_in = const_cast<Bytef*>(in.data());
  d.zs.avail_in = static_cast<uInt>(in.size());
  // Out through a small buffer, so that a part holds what it compressed to and no more.
  const int flush = last ? Z_FINISH : Z_SYNC_FLUSH;
  std::uint8_t buf[1 << 15];
  for (;;) {
    d.zs.next_out = buf;
    d.zs.avail_out = sizeof buf;
    const int rc = deflate(&d.zs, flush);
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) return p;
    p.deflated.insert(p.deflated.end(), buf, buf + (sizeof buf - d.zs.avail_out));
    if (last ? rc == Z_STREAM_END : (d.zs.avail_in == 0 && d.zs.avail_out > 0)) break;
    if (rc == Z_BUF_ERROR && d.zs.avail_out > 0) return p;  // no progress possible
  }
  p.ok = d.zs.avail_in == 0;
  return p;
}

/// The PNG file of `image`: signature, IHDR, the image data as one zlib stream compressed in
/// parts in parallel (one IDAT chunk each), IEND. Nothing else: no time stamp, no gamma chunk.
std::string encode_png(const std::string& path, const Image8& image) {
  const std::size_t row = std::size_t(image.width) * image.channels + 1;
  const int rows_per_part = static_cast<int>(std::max<std::size_t>(1, kPartBytes / row));
  const int parts = (image.height + rows_per_part - 1) / rows_per_part;
  std::vector<Part> deflated(static_cast<std::size_t>(parts));
  tbb::parallel_for(0, parts, [&](int k) {
    const int y0 = k * rows_per_part, y1 = std::min(image.height, y0 + rows_per_part);
    deflated[static_cast<std::size_t>(k)] =
        deflate_part(filtered_rows(image, y0, y1), k == parts - 1);
  });

  std::string out = "\x89PNG\r\n\x1a\n";
  std::vector<std::uint8_t> ihdr;
  put_u32(ihdr, static_cast<std::uint32_t>(image.width));
  put_u32(ihdr, static_cast<std::uint32_t>(image.height));
  // Bit depth 8; colour type 2 (RGB) or 6 (RGBA); deflate; adaptive filtering; no interlace.
  ihdr.insert(ihdr.end(), {8, static_cast<std::uint8_t>(image.channels == 4 ? 6 : 2), 0, 0, 0});
  put_chunk(out, "IHDR", ihdr);
  uLong adler = adler32(0L, nullptr, 0);
  for (std::size_t k = 0; k < deflated.size(); ++k) {
    Part& p = deflated[k];
    if (!p.ok) throw Error("cannot write '" + path + "': zlib failed to compress the image");
    adler = adler32_combine(adler, p.adler, static_cast<z_off_t>(p.size));
    // The stream's zlib header (deflate, 32 KiB window, default level) before the first part, its
    // Adler-32 after the last.
    if (k == 0) p.deflated.insert(p.deflated.begin(), {0x78, 0x9c});
    if (k + 1 == deflated.size()) put_u32(p.deflated, static_cast<std::uint32_t>(adler));
    put_chunk(out, "IDAT", p.deflated);
  }
  put_chunk(out, "IEND", {});
  return out;
}

}  // namespace

void write_png(const std::string& path, const Image8& image) {
  if (image.width <= 0 || image.height <= 0 || (image.channels != 3 && image.channels != 4)) {
    throw Error("cannot write '" + path + "': empty image");
  }
  if (std::size_t(image.width) * image.channels > kMaxRowBytes) {
    throw Error("cannot write '" + path + "': a row of " + std::to_string(image.width) +
                " pixels is too long (at most " +
                std::to_string(kMaxRowBytes / static_cast<std::size_t>(image.channels)) + ")");
  }
  if (image.data.size() != std::size_t(image.width) * image.height * image.channels) {
    throw Error("cannot write '" + path + "': the pixel data does not match the image's size");
  }
  write_text_atomically(path, encode_png(path, image));  // binary: the bytes as they are
}

Image8 read_png(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str())) {
    throw Error("cannot read PNG '" + path + "': " + img.message);
  }
  const bool alpha = (img.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  img.format = alpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  Image8 out(static_cast<int>(img.width), static_cast<int>(img.height), alpha ? 4 : 3);
  if (!png_image_finish_read(&img, nullptr, out.data.data(), 0, nullptr)) {
    png_image_free(&img);
    throw Error("cannot read PNG '" + path + "': " + img.message);
  }
  return out;
}

std::uint8_t to_byte(double v) {
  if (!(v > 0.0)) return 0;
  if (v >= 1.0) return 255;
  return static_cast<std::uint8_t>(std::lround(std::pow(v, 1.0 / 2.2) * 255.0));
}

}  // namespace iaa::app
