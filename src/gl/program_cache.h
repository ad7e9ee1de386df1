// Shader programs from files under one root, built once and cached by
// (files, defines). The loader
//  - resolves `#include "file"` (relative to the including file, then <root>/include),
//    rejecting include cycles and missing files with file:line errors;
//  - emits `#line N S` markers, so the driver's messages name the real file and line
//    (Mesa's "S:N(C): ..." and NVIDIA's "S(N) : ..." are both mapped back);
//  - records every file a program reads, so hot reload rebuilds exactly the programs
//    that depend on a changed file and keeps the last good program when it fails.
#ifndef VOXGI_GL_PROGRAM_CACHE_H
#define VOXGI_GL_PROGRAM_CACHE_H

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gl/handles.h"

namespace voxgi::gl {

struct ProgramDesc {
  std::vector<std::string> files;    // relative to the root; stage from the extension
  std::vector<std::string> defines;  // "NAME" or "NAME=VALUE"
  std::string key() const;
};

// Source with includes expanded; files[i] is the file behind `#line N i`.
struct PreprocessedSource {
  std::string text;
  std::vector<std::filesystem::path> files;
};
PreprocessedSource preprocessShader(const std::filesystem::path& file,
                                    const std::filesystem::path& root,
                                    const std::vector<std::string>& defines);

// Rewrites a driver info log's "S:N(C):" / "S(N) :" prefixes to "file:N:".
std::string mapCompilerLog(const std::string& log, const std::vector<std::filesystem::path>& files);

class Program {
 public:
  GLuint id() const { return object_.id(); }
  const std::string& name() const { return name_; }
  // Bumped on every successful (re)build; passes re-query what they cache when it changes.
  int generation() const { return generation_; }

 private:
  friend class ProgramCache;
  ProgramDesc desc_;
  std::string name_;
  ProgramObject object_;
  int generation_ = 0;
  std::map<std::filesystem::path, std::filesystem::file_time_type> deps_;
};

class ProgramCache {
 public:
  explicit ProgramCache(std::filesystem::path root);

  // Builds on first use; a failure then throws voxgi::Error ("file:line: message").
  const Program& get(const ProgramDesc& desc);

  struct ReloadReport {
    int rebuilt = 0;
    int failed = 0;
    std::string error;  // the first failure, mapped to file:line
  };
  // Rebuilds the programs whose files changed since they were last built.
  ReloadReport reloadChanged();

  const std::filesystem::path& root() const { return root_; }
  size_t size() const { return programs_.size(); }

 private:
  // Compiles and links; returns an empty object and sets *error on failure.
  ProgramObject build(const ProgramDesc& desc, std::string* error,
                      std::map<std::filesystem::path, std::filesystem::file_time_type>* deps);

  std::filesystem::path root_;
  std::map<std::string, std::unique_ptr<Program>> programs_;
};

}  // namespace voxgi::gl

#endif  // VOXGI_GL_PROGRAM_CACHE_H
