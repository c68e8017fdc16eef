// Writes a Cairo image surface as a PNG file through libpng, with the "sub"
// filter and run-length coding: Cairo's own writer uses libpng's defaults,
// which on a tissue snapshot (a mostly flat picture) cost more than drawing it.
// An image of at most 256 colours (a snapshot) is written as a palette.
#pragma once

#include <cairo.h>

#include <filesystem>
#include <string>

namespace fibrodem::cairo {

// Throws std::runtime_error naming the file if it cannot be written.
void write_png_file(cairo_surface_t* image, const std::filesystem::path& file);

// The same PNG as bytes in memory (a picture embedded in a page).
std::string png_bytes(cairo_surface_t* image);

}  // namespace fibrodem::cairo
