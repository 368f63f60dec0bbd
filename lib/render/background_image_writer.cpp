#include "render/background_image_writer.h"

#include <stdexcept>
#include <utility>

#include "render/write_image.h"
#include "splatkit/seconds_since.h"

namespace splatkit::render {

BackgroundImageWriter::~BackgroundImageWriter() {
  if (pending_.valid()) pending_.wait();  // the result (and its uncommitted file) is dropped
}

void BackgroundImageWriter::start(Framebuffer frame, const std::string& path, bool commit) {
  if (busy()) throw std::logic_error("BackgroundImageWriter::start: an image is in flight");
  pending_ = std::async(std::launch::async, [frame = std::move(frame), path, commit]() mutable {
    const auto t0 = Clock::now();
    auto file = std::make_unique<OutputFile>(path);
    write_image(frame, *file);
    if (commit) file->commit();
    return Written{std::move(frame), std::move(file), seconds_since(t0)};
  });
}

BackgroundImageWriter::Written BackgroundImageWriter::wait() {
  if (!busy()) throw std::logic_error("BackgroundImageWriter::wait: no image in flight");
  return pending_.get();
}

}  // namespace splatkit::render
