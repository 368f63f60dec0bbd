// splat-info: describe point-cloud and splat files (format, counts, attributes, bounds, chunks).
#include <cstdio>
#include <iostream>

#include "formats/describe_cloud.h"
#include "formats/read_cloud.h"
#include "splatkit/error.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "splat-info",
      "Describe point-cloud and splat files: format, point and face counts, "
      "attributes with ranges, bounding box, format header, .splk chunks and metadata.",
      "  $ splat-info scan.ply\n"
      "  $ splat-info --json model.splk | jq .points\n"
      "  $ estimate-normals scan.las - | splat-info -\n"
      "  $ splat-info --columns x,y,z,_,r,g,b points.txt\n");
  std::vector<std::string> files;
  bool json = false;
  splatkit::ReadOptions read;
  tool.app().add_option("FILE", files, "Files to describe ('-' = stdin)")->required();
  tool.app().add_flag("--json", json,
                      "Print a JSON report (an array when several files are given)");
  tool.app().add_option("--columns", read.columns,
                        "Column layout of text files, e.g. x,y,z,nx,ny,nz,r,g,b ('_' skips)");
  return tool.run(argc, argv, [&] {
    nlohmann::json reports = nlohmann::json::array();
    for (std::size_t i = 0; i < files.size(); ++i) {
      splatkit::InputStream in(files[i]);
      auto bytes = in.size_hint();
      splatkit::LoadedCloud doc = splatkit::read_cloud(in, read);
      if (!bytes) bytes = in.offset();
      nlohmann::json report = splatkit::describe_cloud(doc, files[i], bytes);
      if (json) {
        reports.push_back(std::move(report));
      } else {
        if (i > 0) std::cout << "\n";
        std::cout << splatkit::describe_cloud_text(report);
      }
    }
    if (json) std::cout << (reports.size() == 1 ? reports[0] : reports).dump(2) << "\n";
    std::cout.flush();
    if (!std::cout) splatkit::throw_output("-", "cannot write the report");
  });
}
