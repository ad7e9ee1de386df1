// The voxgi executable. Only this file decides to exit.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app/cli.h"

int main(int argc, char** argv) {
  using namespace voxgi;
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    const app::Invocation inv = app::parseCommandLine(args);
    switch (inv.command) {
      case app::Command::kHelp:
        std::fputs(inv.helpTopic == "render"    ? app::renderHelp().c_str()
                   : inv.helpTopic == "view"    ? app::viewHelp().c_str()
                   : inv.helpTopic == "bench"   ? app::benchHelp().c_str()
                   : inv.helpTopic == "compare" ? app::compareHelp().c_str()
                                                : app::mainHelp().c_str(),
                   stdout);
        return 0;
      case app::Command::kVersion:
        std::puts(app::versionText().c_str());
        return 0;
      case app::Command::kRender:
        return app::runRender(inv.render);
      case app::Command::kView:
        return app::runView(inv.view);
      case app::Command::kBench:
        return app::runBench(inv.bench);
      case app::Command::kCompare:
        return app::runCompare(inv.compare);
    }
  } catch (const app::UsageError& e) {
    std::fprintf(stderr, "voxgi: error: %s\n", e.what());
    return 2;
  } catch (const Error& e) {
    std::fprintf(stderr, "voxgi: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "voxgi: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "voxgi: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
