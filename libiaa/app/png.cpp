// PNG reading and writing through libpng (png.h). Application layer: used by tools/ and viz/,
// never by the library modules.
#include "app/png.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "app/files.h"
#include "core/error.h"

namespace iaa::app {

void write_png(const std::string& path, const Image8& image) {
  if (image.width <= 0 || image.height <= 0 || (image.channels != 3 && image.channels != 4)) {
    throw Error("cannot write '" + path + "': empty image");
  }
  write_atomically(path, [&](const std::string& tmp) {
    std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(tmp.c_str(), "wb"), &std::fclose);
    if (!f) throw Error("cannot write '" + path + "'");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
      png_destroy_write_struct(&png, &info);
      throw Error("cannot write '" + path + "': libpng failed to start");
    }
    if (setjmp(png_jmpbuf(png))) {
      png_destroy_write_struct(&png, &info);
      throw Error("cannot write '" + path + "': libpng error");
    }
    png_init_io(png, f.get());
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
                 static_cast<png_uint_32>(image.height), 8,
                 image.channels == 4 ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < image.height; ++y) {
      png_write_row(png, const_cast<png_bytep>(image.at(0, y)));
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (std::fflush(f.get()) != 0) throw Error("cannot write '" + path + "': disk full?");
  });
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
