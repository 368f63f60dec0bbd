// Writes images on a thread of its own while the caller renders the next frame (splat-view's
// turntables): one image in flight at a time, each through write_image() into its own
// OutputFile, so every file holds the bytes a plain write_image() call gives, whatever the timing
// and the thread count.
//
// Failure rules are those of writing in sequence: an image whose encoding or writing fails leaves
// no temporary file behind (OutputFile) and its error is rethrown by wait(); files asked to be
// committed are committed by the writer thread as soon as they are written, the others are handed
// back written but not committed (splat-view commits its last image after the report). The
// destructor waits for the image in flight and drops its result: an uncommitted file is removed.
#pragma once

#include <future>
#include <memory>
#include <string>

#include "render/framebuffer.h"
#include "splatkit/output_file.h"

namespace splatkit::render {

class BackgroundImageWriter {
 public:
  struct Written {
    Framebuffer frame;                 // the frame written, handed back for reuse
    std::unique_ptr<OutputFile> file;  // committed if asked, else written only
    double seconds = 0;                // encoding and writing, wall clock
  };

  BackgroundImageWriter() = default;
  ~BackgroundImageWriter();
  BackgroundImageWriter(const BackgroundImageWriter&) = delete;
  BackgroundImageWriter& operator=(const BackgroundImageWriter&) = delete;

  // Starts writing `frame` to `path` (the format follows its extension, write_image.h), and
  // committing it when `commit`. Throws std::logic_error while an image is in flight (wait()
  // first).
  void start(Framebuffer frame, const std::string& path, bool commit);

  // Whether an image was started and not yet waited for.
  bool busy() const { return pending_.valid(); }

  // Waits for the image in flight and returns it; rethrows its error (those of write_image():
  // Error(kOutput) naming the file, Error(kUsage) for a format that cannot be written,
  // Error(kUnsupported); std::bad_alloc). Throws std::logic_error when nothing is in flight.
  Written wait();

 private:
  std::future<Written> pending_;
};

}  // namespace splatkit::render
