// The options of `voxgi render` and `voxgi view`, in one table: each option's name,
// its value, the commands that take it, its help and how it is applied. The parser
// (app/cli.cpp) and the help of both commands are made from it, so an option is
// written once; tests/app/cli_parse_test.cpp checks that the README's option table
// names only options the table holds.
#ifndef VOXGI_APP_CLI_OPTIONS_H
#define VOXGI_APP_CLI_OPTIONS_H

#include <string>
#include <vector>

#include "app/cli.h"

namespace voxgi::app {

// Where an option puts its value: the render settings both commands share, and the
// options of the command being parsed (the other is null).
struct OptionTargets {
  render::RenderSettings* settings = nullptr;
  RenderOptions* render = nullptr;
  ViewOptions* view = nullptr;
};

// The commands an option belongs to (a bit set).
enum OptionCommands : unsigned { kRenderOption = 1u, kViewOption = 2u, kBothOptions = 3u };

// The part of `render --help` an option is listed in.
enum class OptionSection { kGeneral, kRtgi, kPathtrace };

struct CliOption {
  const char* name;   // "--size"
  const char* alias;  // "-o", or nullptr
  const char* value;  // what follows it in the help ("WxH"); nullptr: a flag
  unsigned commands;  // OptionCommands
  OptionSection section;
  // The help text, its lines at most 58 characters (they start at column 20).
  const char* help;
  // view's own text; nullptr: view's help lists the option among those "as for
  // voxgi render". Ignored for options of one command.
  const char* viewHelp;
  // Applies the option; `value` is empty for a flag. Throws UsageError.
  void (*apply)(const OptionTargets& to, const std::string& value);
};

// `v` as an integer in [lo, hi]; a UsageError naming `flag` otherwise.
int parseIntValue(const std::string& flag, const std::string& v, int lo, int hi);

// Every option, in the order the help lists them.
const std::vector<CliOption>& cliOptions();
// The option named `name` (or by its alias) that `command` takes, or nullptr.
const CliOption* findCliOption(const std::string& name, OptionCommands command);
// The help's lines for the options `command` takes in `section`; for view,
// `section` is ignored, the options with a text of their own come first, then one
// list of those "as for voxgi render".
std::string cliOptionsHelp(OptionCommands command, OptionSection section);

}  // namespace voxgi::app

#endif  // VOXGI_APP_CLI_OPTIONS_H
