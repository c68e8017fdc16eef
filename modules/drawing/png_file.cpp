#include "png_file.hpp"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace fibrodem::cairo {

namespace {

// The image's colours as a palette and each pixel's index in it, if it has
// at most 256 colours (a snapshot: its cells take the colour bar's 200
// colours); else false. Runs of one colour, most of the picture, take the
// last colour found without a look-up.
bool palette_of(const unsigned char* data, int width, int height, int stride,
                std::vector<std::uint32_t>& colours, std::vector<png_byte>& indices) {
  constexpr std::size_t kSlots = 1024;  // open addressing, at most a quarter full
  std::vector<std::int16_t> slot(kSlots, -1);
  colours.clear();
  indices.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  std::uint32_t last = 0xffffffff;
  png_byte last_index = 0;
  for (int y = 0; y < height; ++y) {
    const auto* pixels = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    png_byte* out = indices.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
    for (int x = 0; x < width; ++x) {
      const std::uint32_t colour = pixels[x] & 0xffffff;
      if (colour != last) {
        std::size_t h = (colour * 2654435761u) >> 22;  // (Knuth's multiplicative hash, 10 bits)
        while (slot[h] >= 0 && colours[static_cast<std::size_t>(slot[h])] != colour) h = (h + 1) % kSlots;
        if (slot[h] < 0) {
          if (colours.size() == 256) return false;
          slot[h] = static_cast<std::int16_t>(colours.size());
          colours.push_back(colour);
        }
        last = colour;
        last_index = static_cast<png_byte>(slot[h]);
      }
      out[x] = last_index;
    }
  }
  return true;
}

}  // namespace

namespace {
void append_bytes(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), length);
}
void flush_nothing(png_structp) {}

// Into `out` if given, else appended to `bytes`; `file` names it in errors.
void encode_png(cairo_surface_t* image, const std::filesystem::path& file, FILE* out_file, std::string* bytes) {
  cairo_surface_flush(image);
  const int width = cairo_image_surface_get_width(image), height = cairo_image_surface_get_height(image);
  const int stride = cairo_image_surface_get_stride(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  if (data == nullptr || cairo_image_surface_get_format(image) != CAIRO_FORMAT_RGB24)
    throw std::runtime_error("write_png_file: expected an RGB24 image surface for " + file.string());

  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("write_png_file: libpng could not start for " + file.string());
  }
  // RGB24 is one 32-bit word per pixel, 0x00RRGGBB in native byte order.
  std::vector<png_byte> row(3 * static_cast<std::size_t>(width));
  // At most 256 colours: one byte per pixel into a palette, a third of the
  // bytes for zlib (a Fig. 3 snapshot: 4.2 instead of 6.4 ms).
  std::vector<std::uint32_t> colours;
  std::vector<png_byte> indices;
  const bool by_palette = palette_of(data, width, height, stride, colours, indices);
  std::vector<png_color> palette;
  for (std::uint32_t c : colours)
    palette.push_back({static_cast<png_byte>(c >> 16), static_cast<png_byte>(c >> 8), static_cast<png_byte>(c)});
  // libpng reports errors by longjmp to here (it is C: no exception may cross it).
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("cannot write " + file.string());
  }
  {
    if (out_file) png_init_io(png, out_file);
    else png_set_write_fn(png, bytes, append_bytes, flush_nothing);
    // Flat colours: the "sub" filter turns runs into zeros, which run-length
    // coding packs at memory speed.
    // (Indices are no quantities: unfiltered, as the PNG spec advises.)
    png_set_filter(png, PNG_FILTER_TYPE_BASE, by_palette ? PNG_FILTER_NONE : PNG_FILTER_SUB);
    png_set_compression_strategy(png, Z_RLE);
    png_set_compression_level(png, Z_BEST_SPEED);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
                 by_palette ? PNG_COLOR_TYPE_PALETTE : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (by_palette) png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
    png_write_info(png, info);
    for (int y = 0; by_palette && y < height; ++y)
      png_write_row(png, indices.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width));
    for (int y = 0; !by_palette && y < height; ++y) {
      const auto* pixels = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
      for (int x = 0; x < width; ++x) {
        row[3 * x] = static_cast<png_byte>(pixels[x] >> 16);
        row[3 * x + 1] = static_cast<png_byte>(pixels[x] >> 8);
        row[3 * x + 2] = static_cast<png_byte>(pixels[x]);
      }
      png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
  }
  png_destroy_write_struct(&png, &info);
}
}  // namespace

void write_png_file(cairo_surface_t* image, const std::filesystem::path& file) {
  std::unique_ptr<FILE, decltype(&std::fclose)> out(std::fopen(file.c_str(), "wb"), &std::fclose);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  encode_png(image, file, out.get(), nullptr);
  if (std::fflush(out.get()) != 0) throw std::runtime_error("cannot write " + file.string());
}

std::string png_bytes(cairo_surface_t* image) {
  std::string bytes;
  encode_png(image, "a PNG in memory", nullptr, &bytes);
  return bytes;
}

}  // namespace fibrodem::cairo
