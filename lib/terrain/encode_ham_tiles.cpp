#include "terrain/encode_ham_tiles.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cstring>
#include <exception>

#include "splatkit/error.h"

namespace splatkit::terrain {

namespace {

class MemoryStream final : public Imf::OStream {
 public:
  MemoryStream() : Imf::OStream("tiles.exr") {}
  void write(const char c[], int n) override {
    if (pos_ + uint64_t(n) > bytes.size()) bytes.resize(std::size_t(pos_ + uint64_t(n)));
    std::memcpy(bytes.data() + pos_, c, std::size_t(n));
    pos_ += uint64_t(n);
  }
  uint64_t tellp() override { return pos_; }
  void seekp(uint64_t pos) override { pos_ = pos; }
  std::vector<unsigned char> bytes;

 private:
  uint64_t pos_ = 0;
};

}  // namespace

std::vector<unsigned char> encode_ham_tiles(const HamTiles& t) {
  try {
    const int w = int(t.tiles_x), h = int(t.tiles_y);
    Imf::Header header(w, h);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.channels().insert("ham_max", Imf::Channel(Imf::FLOAT));
    header.channels().insert("h_max", Imf::Channel(Imf::FLOAT));
    header.channels().insert("x", Imf::Channel(Imf::UINT));
    header.channels().insert("y", Imf::Channel(Imf::UINT));
    header.channels().insert("voids", Imf::Channel(Imf::UINT));
    header.insert("splatkit:tile_size", Imf::IntAttribute(int(t.tile)));
    header.insert("splatkit:width", Imf::IntAttribute(int(t.width)));
    header.insert("splatkit:height", Imf::IntAttribute(int(t.height)));
    header.insert("splatkit:z_scale", Imf::FloatAttribute(float(t.z_scale)));
    header.insert("splatkit:ham", Imf::StringAttribute(t.header.dump()));
    Imf::FrameBuffer fb;
    auto slice = [&](const char* name, Imf::PixelType type, const void* data) {
      fb.insert(name, Imf::Slice(type, static_cast<char*>(const_cast<void*>(data)), 4,
                                 std::size_t(4) * std::size_t(w)));
    };
    slice("ham_max", Imf::FLOAT, t.ham_max.data());
    slice("h_max", Imf::FLOAT, t.h_max.data());
    slice("x", Imf::UINT, t.x.data());
    slice("y", Imf::UINT, t.y.data());
    slice("voids", Imf::UINT, t.voids.data());
    MemoryStream stream;
    {
      Imf::OutputFile file(stream, header, 1);
      file.setFrameBuffer(fb);
      file.writePixels(h);
    }
    return std::move(stream.bytes);
  } catch (const std::exception& e) {
    throw Error(ErrorKind::kInternal, std::string("OpenEXR failed to encode the tiles: ") + e.what());
  }
}

}  // namespace splatkit::terrain
