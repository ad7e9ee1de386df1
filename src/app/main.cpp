// The voxgi executable. Only this file decides to exit.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/environment.h"
#include "core/memory.h"

namespace {

// Transparent huge pages for the memory glibc's malloc maps. A software rasterizer
// (llvmpipe) keeps every buffer and texture in malloc'd memory and reads it at
// random, so with 4 KiB pages much of its time goes to TLB misses: on the reference
// machine 2 MiB pages make the points view of a 256^3 grid 1.6x faster (README, GL
// layer). glibc (2.35 and later) reads the tunable only at start-up, so voxgi
// starts itself again with it set, once; where exec fails it goes on with normal
// pages. VOXGI_HUGE_PAGES=0 turns this off (under valgrind,
// say, which does not follow an exec by default). The kernel decides in the end:
// with transparent_hugepage set to "never" nothing changes.
void startWithHugePages(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  const char* setting = std::getenv("VOXGI_HUGE_PAGES");
  if (setting && std::string(setting) == "0") return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string old = tunables ? tunables : "";
  if (old.find("glibc.malloc.hugetlb") != std::string::npos) return;  // set: keep it
  const std::string t = old.empty() ? "glibc.malloc.hugetlb=1" : old + ":glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", t.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  if (tunables)  // exec failed: as we were
    setenv("GLIBC_TUNABLES", old.c_str(), 1);
  else
    unsetenv("GLIBC_TUNABLES");
#else
  (void)argv;
#endif
}

}  // namespace

int main(int argc, char** argv) {
  using namespace voxgi;
  startWithHugePages(argv);
  pauseHugePages(true);  // until the first frame is drawn (core/memory.h)
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    app::Invocation inv = app::parseCommandLine(args);
    app::applyEnvironment(&inv);
    switch (inv.command) {
      case app::Command::kHelp:
        std::fputs(inv.helpTopic == "render"    ? app::renderHelp().c_str()
                   : inv.helpTopic == "view"    ? app::viewHelp().c_str()
                   : inv.helpTopic == "bench"   ? app::benchHelp().c_str()
                   : inv.helpTopic == "compare" ? app::compareHelp().c_str()
                   : inv.helpTopic == "check"   ? app::checkHelp().c_str()
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
      case app::Command::kCheck:
        return app::runCheck(inv.check);
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
