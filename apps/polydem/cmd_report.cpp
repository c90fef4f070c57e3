// polydem report contact-types: the contact-type table of every kernel (BENCHMARKS.md section C),
// written as Markdown and JSON.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "commands.h"
#include "contact_type_report.h"
#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::app {

namespace {

void writeFile(const std::filesystem::path& path, const std::string& text) {
  const auto tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << text;
    if (!out) throw Error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace

int reportCommand(int argc, char** argv) {
  Args args(argc, argv, {"help"});
  const bool help = args.flag("help");
  if (help || args.positional().empty() || args.positional()[0] != "contact-types") {
    std::printf(
        "usage: polydem report contact-types [--out DIR] [--kernels a,b,...] [--poses N] "
        "[--seed S]\n  writes DIR/contact-types.md and DIR/contact-types.json (default DIR: .)\n");
    return help ? 0 : 2;
  }
  const std::string out_dir = args.value("out", ".");
  const auto kernels = split(args.value("kernels", join(contact::kernelNames(), ",")), ',');
  const int poses = static_cast<int>(args.integer("poses", 20, 1));
  const auto seed =
      static_cast<unsigned>(args.integer("seed", 2024, 0, std::numeric_limits<unsigned>::max()));
  args.rejectUnknown();
  if (mpi::rank() != 0) return 0;

  const auto rows = contactTypeRows(kernels, poses, seed);
  const std::string md =
      "# Contact types (BENCHMARKS.md section C)\n\n" + contactTypeMarkdown(rows, kernels);
  std::filesystem::create_directories(out_dir);
  writeFile(std::filesystem::path(out_dir) / "contact-types.md", md);
  writeFile(std::filesystem::path(out_dir) / "contact-types.json",
            contactTypeJson(rows).dump(2) + "\n");
  std::printf("%s\nwritten: %s/contact-types.md, %s/contact-types.json\n", md.c_str(),
              out_dir.c_str(), out_dir.c_str());
  return 0;
}

}  // namespace polydem::app
