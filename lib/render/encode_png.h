// PNG encoding of 8-bit RGB images, made for speed: a turntable writes many large frames.
//
// The file ([PNG] in docs/references.md): signature, IHDR (8-bit RGB, not interlaced), sRGB
// (perceptual intent) with the gAMA and cHRM chunks the standard recommends beside it, one IDAT,
// IEND. Every row uses the Up filter (type 2: the byte above subtracted, the first row as is);
// the zlib stream ([RFC1950], [RFC1951]) is made by zlib at level 1 with its run-length strategy
// (matches at distance 1 only). Rendered frames are large smooth regions and a flat background:
// against libpng's defaults (level 6, a filter chosen per row) a 1920x1080 frame encodes 4-5x
// faster into a file 10-45 % larger. The same pixels always give the same bytes.
#pragma once

#include <cstdint>
#include <vector>

namespace splatkit::render {

// `rgb`: #height×width×3 bytes, rows top first; width and height in [1, 2^31 − 1]. Throws
// std::bad_alloc when memory runs out, std::invalid_argument for a bad size, std::runtime_error if
// zlib fails (it does not on valid input).
std::vector<uint8_t> encode_png(const uint8_t* rgb, int width, int height);

}  // namespace splatkit::render
