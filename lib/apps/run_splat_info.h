// splat-info's work, callable without the command line: describe point-cloud and splat files
// (formats/describe_cloud.h) as text or JSON.
//
// A file that cannot be read does not stop the others: its error goes to `err` as
// "splat-info: <file>: <cause>" and the good files are still described (text, or a JSON array
// when several files are given, so that `splat-info --json scans/*.ply > inventory.json` lists
// every readable scan). Then the first failure is thrown: alone when it was the only file, else
// as Error(<its kind>) "<k> of <n> files could not be described".
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "formats/read_cloud.h"

namespace splatkit::apps {

struct SplatInfoOptions {
  std::vector<std::string> files;  // "-" = standard input
  bool json = false;               // JSON (an object for one file, an array for several)
  ReadOptions read;                // read.columns: text files' column layout
};

// Throws Error(kOutput) when `out` fails.
void run_splat_info(const SplatInfoOptions& options, std::ostream& out, std::ostream& err);

}  // namespace splatkit::apps
