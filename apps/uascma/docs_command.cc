// uascma docs — documents generated from the code: `docs input-bounds` writes docs/input-bounds.md's table of
// campaign keys from the field table (campaign/config_fields.h, campaign/input_bounds_doc.h).
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "uascma/campaign/input_bounds_doc.h"
#include "uascma/common/files.h"

namespace uascma::cli {

void AddDocsCommand(CLI::App& app) {
  struct Options {
    std::string file = "docs/input-bounds.md";
    bool write = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* docs = app.add_subcommand("docs", "Documents generated from the code");
  docs->require_subcommand(1);
  CLI::App* bounds =
      docs->add_subcommand("input-bounds",
                           "docs/input-bounds.md with its campaign-key table generated from the field table "
                           "(campaign/config_fields.h): printed, or written in place with --write");
  bounds->add_option("--file", options->file, "The document (default docs/input-bounds.md, from the source folder)");
  bounds->add_flag("--write", options->write, "Rewrite the file instead of printing it");
  bounds->callback([options] {
    const std::string text = campaign::WithGeneratedBounds(ReadFile(options->file), options->file);
    if (options->write) {
      WriteFileAtomically(options->file, text);
    } else {
      std::cout << text;
    }
  });
}

}  // namespace uascma::cli
