// splat-view --serve: a small HTTP server (cpp-httplib) for the browser viewer (web/), bound to
// the loopback interface 127.0.0.1 only.
//
// What it answers (GET and HEAD; anything else is 404):
//   /                   the viewer page; /<asset> the page's other files, embedded in the binary
//                       at build time (viewer_assets.h), so nothing is fetched from elsewhere;
//   /files.json         {"files": [NAME, ...]}: the names served, in the order given;
//   /files/NAME         the file's bytes as they are on disk (single and multiple Range
//                       requests: 206 Partial Content);
//   /model/NAME         its view model (encode_view_model.h), decoded on first request and kept.
// NAME is a served file's base name (its last path component), compared as an exact string with
// the decoded request path: nothing else on the disk can be named, whatever the path holds
// ("..", "%2e%2e", "/", absolute paths, other files of the same directory).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace splatkit::serve {

struct ServeOptions {
  std::vector<std::string> files;  // paths; their base names must differ
  int port = 0;                    // 0: any free port
};

// Checks the files (each must be a readable regular file, base names distinct: Error(kUsage) or
// Error(kBadInput) otherwise), binds 127.0.0.1:port (Error(kOutput) when it cannot), calls
// `on_ready` with the viewer's URL ("http://127.0.0.1:PORT/"), then serves until the process
// receives SIGINT or SIGTERM, and returns normally. Must be called before the process starts
// other threads that could take those signals (the tools' main thread is).
void serve_files(const ServeOptions& options,
                 const std::function<void(const std::string& url)>& on_ready);

}  // namespace splatkit::serve
