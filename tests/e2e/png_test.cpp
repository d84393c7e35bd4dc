// The PNG writer (app/png.h, our encoder over zlib, compressed in parts in parallel): every file
// it writes is a valid PNG whose pixels are the image's exactly, read back by libpng and decoded
// by hand (chunk CRCs, one zlib stream whose Adler-32 zlib checks, Sub-filtered rows); the bytes
// depend on the pixels alone, not on the threads; bad input is a clear error and leaves no file.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "app/files.h"
#include "app/png.h"
#include "core/error.h"

namespace {

namespace fs = std::filesystem;
using iaa::app::Image8;

/// A fresh directory under the system's temporary one, removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    path =
        fs::temp_directory_path() / ("iaa-png-test-" + std::to_string(std::random_device{}()) +
                                     "-" + std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

/// The file's bytes (app/files.h).
std::string file_bytes(const fs::path& p) {
  return iaa::app::read_file(p.string());
}

/// An image of noise over smooth gradients and flat runs (as renders have), from `seed`.
Image8 test_image(int w, int h, int channels, unsigned seed) {
  Image8 img(w, h, channels);
  std::mt19937 rng(seed);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < channels; ++c) {
        const int kind = (x / 7 + y / 5) % 3;
        img.at(x, y)[c] = static_cast<std::uint8_t>(kind == 0   ? 255
                                                    : kind == 1 ? (x * 3 + y + c * 40) & 255
                                                                : rng() & 255);
      }
    }
  }
  return img;
}

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return std::uint32_t(b[at]) << 24 | std::uint32_t(b[at + 1]) << 16 |
         std::uint32_t(b[at + 2]) << 8 | std::uint32_t(b[at + 3]);
}

/// Decodes `png` by hand, failing the test on any defect: signature, chunk order and CRCs, IHDR,
/// the IDAT stream (zlib checks its header and Adler-32), one filter byte per row (0-4), and the
/// unfiltered rows. Returns the pixels.
Image8 strict_decode(const std::string& file) {
  const std::vector<std::uint8_t> png(file.begin(), file.end());
  const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_GE(png.size(), 8u);
  EXPECT_TRUE(std::equal(signature, signature + 8, png.begin()));
  std::vector<std::string> types;
  std::vector<std::uint8_t> ihdr, idat;
  for (std::size_t at = 8; at < png.size();) {
    EXPECT_LE(at + 12, png.size());
    const std::uint32_t n = be32(png, at);
    EXPECT_LE(at + 12 + n, png.size());
    const std::string type(png.begin() + static_cast<std::ptrdiff_t>(at + 4),
                           png.begin() + static_cast<std::ptrdiff_t>(at + 8));
    const uLong crc = crc32(crc32(0L, nullptr, 0), png.data() + at + 4, 4 + n);
    EXPECT_EQ(crc, be32(png, at + 8 + n)) << type;
    const auto body = png.begin() + static_cast<std::ptrdiff_t>(at + 8);
    if (type == "IHDR") ihdr.assign(body, body + n);
    if (type == "IDAT") idat.insert(idat.end(), body, body + n);
    types.push_back(type);
    at += 12 + n;
  }
  EXPECT_GE(types.size(), 3u);
  EXPECT_EQ(types.front(), "IHDR");
  EXPECT_EQ(types.back(), "IEND");
  for (std::size_t k = 1; k + 1 < types.size(); ++k) EXPECT_EQ(types[k], "IDAT");
  EXPECT_EQ(ihdr.size(), 13u);
  if (ihdr.size() != 13) return {};
  const int w = static_cast<int>(be32(ihdr, 0)), h = static_cast<int>(be32(ihdr, 4));
  EXPECT_EQ(ihdr[8], 8);                         // bit depth
  EXPECT_TRUE(ihdr[9] == 2 || ihdr[9] == 6);     // RGB or RGBA
  EXPECT_EQ(ihdr[10] | ihdr[11] | ihdr[12], 0);  // deflate, filter method 0, no interlace
  const int channels = ihdr[9] == 6 ? 4 : 3;
  const std::size_t row = std::size_t(w) * channels;
  std::vector<std::uint8_t> raw((row + 1) * h);
  uLongf raw_size = raw.size();
  EXPECT_EQ(uncompress(raw.data(), &raw_size, idat.data(), idat.size()), Z_OK);
  EXPECT_EQ(raw_size, raw.size());
  Image8 out(w, h, channels);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* in = &raw[(row + 1) * y];
    const std::uint8_t filter = in[0];
    EXPECT_LE(filter, 4);
    std::uint8_t* o = out.at(0, y);
    const std::uint8_t* up = y > 0 ? out.at(0, y - 1) : nullptr;
    for (std::size_t i = 0; i < row; ++i) {
      const int a = i >= std::size_t(channels) ? o[i - channels] : 0;
      const int b = up ? up[i] : 0;
      const int c = up && i >= std::size_t(channels) ? up[i - channels] : 0;
      int pred = 0;
      if (filter == 1) pred = a;
      if (filter == 2) pred = b;
      if (filter == 3) pred = (a + b) / 2;
      if (filter == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        pred = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
      }
      o[i] = static_cast<std::uint8_t>(in[1 + i] + pred);
    }
  }
  return out;
}

TEST(Png, RoundTripsExactlyThroughLibpngAndAStrictDecoder) {
  TempDir dir;
  // 1x1 up to images of several compressed parts, and rows longer than a part (one row each).
  const int sizes[][2] = {{1, 1}, {3, 2}, {7, 1}, {1, 300}, {500, 500}, {1000, 700}, {40000, 3}};
  unsigned seed = 1;
  for (const auto& wh : sizes) {
    for (int channels : {3, 4}) {
      const Image8 img = test_image(wh[0], wh[1], channels, seed++);
      const fs::path p = dir.path / "a.png";
      iaa::app::write_png(p.string(), img);
      const Image8 back = iaa::app::read_png(p.string());
      ASSERT_EQ(back.width, img.width);
      ASSERT_EQ(back.height, img.height);
      ASSERT_EQ(back.channels, img.channels);
      EXPECT_EQ(back.data, img.data) << wh[0] << "x" << wh[1] << "x" << channels << " (libpng)";
      const Image8 strict = strict_decode(file_bytes(p));
      EXPECT_EQ(strict.data, img.data) << wh[0] << "x" << wh[1] << "x" << channels << " (strict)";
    }
  }
}

TEST(Png, BytesDependOnThePixelsAloneNotOnTheThreads) {
  TempDir dir;
  const Image8 img = test_image(613, 457, 3, 7);
  const fs::path a = dir.path / "a.png", b = dir.path / "b.png";
  iaa::app::write_png(a.string(), img);
  tbb::task_arena one(1);
  one.execute([&] { iaa::app::write_png(b.string(), img); });
  EXPECT_EQ(file_bytes(a), file_bytes(b));
  // A flat image compresses to little: the parts share one stream, not one per part.
  const Image8 white = [] {
    Image8 w(800, 800, 3);
    std::fill(w.data.begin(), w.data.end(), std::uint8_t(255));
    return w;
  }();
  iaa::app::write_png(a.string(), white);
  EXPECT_LT(fs::file_size(a), 8000u);
  EXPECT_EQ(strict_decode(file_bytes(a)).data, white.data);
}

TEST(Png, BadInputIsAClearErrorAndLeavesNoFile) {
  TempDir dir;
  const fs::path p = dir.path / "x.png";
  EXPECT_THROW(iaa::app::write_png(p.string(), Image8(0, 5, 3)), iaa::Error);
  EXPECT_THROW(iaa::app::write_png(p.string(), Image8(5, 5, 2)), iaa::Error);
  Image8 short_data(4, 4, 3);
  short_data.data.resize(10);
  try {
    iaa::app::write_png(p.string(), short_data);
    ADD_FAILURE() << "no error for pixel data shorter than the image";
  } catch (const iaa::Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not match"), std::string::npos) << e.what();
  }
  Image8 too_wide;  // no pixels allocated: the row length is checked first
  too_wide.width = (1 << 30) / 3 + 1;
  too_wide.height = 1;
  try {
    iaa::app::write_png(p.string(), too_wide);
    ADD_FAILURE() << "no error for a row over 1 GiB";
  } catch (const iaa::Error& e) {
    EXPECT_NE(std::string(e.what()).find("is too long (at most 357913941)"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(iaa::app::write_png((dir.path / "missing" / "x.png").string(), Image8(2, 2, 3)),
               iaa::Error);
  EXPECT_TRUE(fs::is_empty(dir.path));
}

}  // namespace
