#include "gl/program_cache.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "core/log.h"

namespace voxgi::gl {
namespace fs = std::filesystem;
namespace {

bool readText(const fs::path& p, std::string* out) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  *out = s.str();
  return true;
}

GLenum stageFromExtension(const fs::path& p) {
  const std::string e = p.extension().string();
  if (e == ".vert") return GL_VERTEX_SHADER;
  if (e == ".frag") return GL_FRAGMENT_SHADER;
  if (e == ".geom") return GL_GEOMETRY_SHADER;
  if (e == ".comp") return GL_COMPUTE_SHADER;
  if (e == ".tesc") return GL_TESS_CONTROL_SHADER;
  if (e == ".tese") return GL_TESS_EVALUATION_SHADER;
  return 0;
}

std::string displayPath(const fs::path& p) {
  std::error_code ec;
  const fs::path rel = fs::relative(p, fs::current_path(ec), ec);
  if (!ec && !rel.empty() && rel.native().rfind("..", 0) != 0) return rel.string();
  return p.string();
}

struct Expander {
  const fs::path& root;
  std::vector<fs::path> files;
  std::vector<fs::path> stack;

  int indexOf(const fs::path& p) {
    for (size_t i = 0; i < files.size(); ++i)
      if (files[i] == p) return static_cast<int>(i);
    files.push_back(p);
    return static_cast<int>(files.size() - 1);
  }

  // Appends `file`'s lines to `out`; the #version line (main file only) is skipped
  // here and emitted by the caller first.
  void expand(const fs::path& file, std::string* out, std::string* versionLine) {
    std::string text;
    if (!readText(file, &text)) throw Error(displayPath(file) + ": cannot read shader file");
    for (const fs::path& s : stack)
      if (s == file) throw Error(displayPath(file) + ": #include cycle");
    stack.push_back(file);
    const int index = indexOf(file);
    static const std::regex includeRe(R"(^\s*#\s*include\s+"([^"]+)\"\s*(//.*)?$)");
    static const std::regex versionRe(R"(^\s*#\s*version\b.*$)");
    std::istringstream in(text);
    std::string line;
    int lineNo = 0;
    *out += strf("#line 1 %d\n", index);
    while (std::getline(in, line)) {
      ++lineNo;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::smatch m;
      if (std::regex_match(line, m, includeRe)) {
        const std::string name = m[1].str();
        fs::path inc = file.parent_path() / name;
        if (!fs::exists(inc)) inc = root / "include" / name;
        if (!fs::exists(inc))
          throw Error(strf("%s:%d: cannot find include \"%s\"", displayPath(file).c_str(), lineNo,
                           name.c_str()));
        expand(fs::weakly_canonical(inc), out, nullptr);
        *out += strf("#line %d %d\n", lineNo + 1, index);
        continue;
      }
      if (std::regex_match(line, versionRe)) {
        if (versionLine && versionLine->empty()) {
          *versionLine = line;
          *out += "\n";  // keep line numbers
          continue;
        }
        throw Error(strf("%s:%d: #version is allowed only at the top of the main shader",
                         displayPath(file).c_str(), lineNo));
      }
      *out += line;
      *out += '\n';
    }
    stack.pop_back();
  }
};

}  // namespace

std::string ProgramDesc::key() const {
  std::string k;
  for (const auto& f : files) k += f + ";";
  k += "|";
  for (const auto& d : defines) k += d + ";";
  return k;
}

PreprocessedSource preprocessShader(const fs::path& file, const fs::path& root,
                                    const std::vector<std::string>& defines) {
  Expander ex{root, {}, {}};
  std::string body, version;
  ex.expand(fs::weakly_canonical(file), &body, &version);
  if (version.empty()) throw Error(displayPath(file) + ":1: missing #version line");
  std::string text = version + "\n";
  for (const std::string& d : defines) {
    const size_t eq = d.find('=');
    text += eq == std::string::npos ? "#define " + d + "\n"
                                    : "#define " + d.substr(0, eq) + " " + d.substr(eq + 1) + "\n";
  }
  text += body;
  return {text, ex.files};
}

std::string mapCompilerLog(const std::string& log, const std::vector<fs::path>& files) {
  static const std::regex mesaRe(R"(^(\d+):(\d+)\((\d+)\):\s*(.*)$)");
  static const std::regex nvRe(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
  std::istringstream in(log);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::smatch m;
    auto name = [&](const std::string& idx) {
      const size_t i = static_cast<size_t>(std::stoul(idx));
      return i < files.size() ? displayPath(files[i]) : "<source " + idx + ">";
    };
    if (std::regex_match(line, m, mesaRe)) {
      out += name(m[1].str()) + ":" + m[2].str() + ":" + m[3].str() + ": " + m[4].str() + "\n";
    } else if (std::regex_match(line, m, nvRe)) {
      out += name(m[1].str()) + ":" + m[2].str() + ": " + m[3].str() + "\n";
    } else {
      out += line + "\n";
    }
  }
  return out;
}

ProgramCache::ProgramCache(fs::path root) : root_(std::move(root)) {}

ProgramObject ProgramCache::build(const ProgramDesc& desc, std::string* error,
                                  std::map<fs::path, fs::file_time_type>* deps) {
  std::vector<ShaderObject> shaders;
  deps->clear();
  ProgramObject program(glCreateProgram());
  for (const std::string& f : desc.files) {
    const fs::path path = root_ / f;
    const GLenum stage = stageFromExtension(path);
    if (stage == 0) {
      *error = displayPath(path) + ": unknown shader stage (extension)";
      return {};
    }
    PreprocessedSource src;
    try {
      src = preprocessShader(path, root_, desc.defines);
    } catch (const Error& e) {
      *error = e.what();
      return {};
    }
    for (const fs::path& p : src.files) {
      std::error_code ec;
      (*deps)[p] = fs::last_write_time(p, ec);
    }
    ShaderObject shader(glCreateShader(stage));
    const char* text = src.text.c_str();
    glShaderSource(shader.id(), 1, &text, nullptr);
    glCompileShader(shader.id());
    GLint ok = 0, len = 0;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    glGetShaderiv(shader.id(), GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
    glGetShaderInfoLog(shader.id(), len, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    if (!ok) {
      const std::string mapped = mapCompilerLog(log, src.files);
      // One line for the error value; the whole log goes to the debug log.
      std::string first = mapped.substr(0, mapped.find('\n'));
      for (size_t p = 0; p < mapped.size();) {
        size_t e = mapped.find('\n', p);
        std::string l = mapped.substr(p, e - p);
        if (l.find("error") != std::string::npos) {
          first = l;
          break;
        }
        if (e == std::string::npos) break;
        p = e + 1;
      }
      logDebug("shader compile log:\n" + mapped);
      *error = first.empty() ? displayPath(path) + ": compile failed" : first;
      return {};
    }
    glAttachShader(program.id(), shader.id());
    shaders.push_back(std::move(shader));
  }
  glLinkProgram(program.id());
  GLint ok = 0, len = 0;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  for (const ShaderObject& s : shaders) glDetachShader(program.id(), s.id());
  if (!ok) {
    glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
    glGetProgramInfoLog(program.id(), len, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    std::string joined;
    for (const auto& f : desc.files) joined += (joined.empty() ? "" : "+") + f;
    *error = strf("%s: link failed: %s", joined.c_str(), log.substr(0, log.find('\n')).c_str());
    return {};
  }
  return program;
}

const Program& ProgramCache::get(const ProgramDesc& desc) {
  const std::string key = desc.key();
  auto it = programs_.find(key);
  if (it != programs_.end()) return *it->second;
  auto p = std::make_unique<Program>();
  p->desc_ = desc;
  for (const auto& f : desc.files) p->name_ += (p->name_.empty() ? "" : "+") + f;
  std::string error;
  p->object_ = build(desc, &error, &p->deps_);
  if (!p->object_) throw Error(error);
  p->generation_ = 1;
  return *programs_.emplace(key, std::move(p)).first->second;
}

ProgramCache::ReloadReport ProgramCache::reloadChanged() {
  ReloadReport report;
  for (auto& [key, p] : programs_) {
    bool changed = false;
    for (auto& [path, stamp] : p->deps_) {
      std::error_code ec;
      auto now = fs::last_write_time(path, ec);
      if (ec) now = fs::file_time_type::min();  // deleted: changed once, then stable
      if (now != stamp) {
        changed = true;
        break;
      }
    }
    if (!changed) continue;
    std::string error;
    std::map<fs::path, fs::file_time_type> deps;
    ProgramObject fresh = build(p->desc_, &error, &deps);
    if (fresh) {
      p->object_ = std::move(fresh);
      p->deps_ = std::move(deps);
      ++p->generation_;
      ++report.rebuilt;
      logInfo("reloaded " + p->name_);
    } else {
      // Keep the last good program; remember the stamps so a broken file is not
      // recompiled every frame, only when it changes again.
      for (auto& [path, stamp] : p->deps_) {
        std::error_code ec;
        const auto now = fs::last_write_time(path, ec);
        stamp = ec ? fs::file_time_type::min() : now;
      }
      for (auto& [path, stamp] : deps) p->deps_.emplace(path, stamp);
      ++report.failed;
      if (report.error.empty()) report.error = error;
      logError("reload failed, keeping the last good program: " + error);
    }
  }
  return report;
}

}  // namespace voxgi::gl
