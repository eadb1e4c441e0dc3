#include "native/native_model.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "codegen/c_expr.h"
#include "codegen/c_runtime.h"
#include "model/expression.h"

extern char** environ;

namespace kfw::native {

namespace {

namespace fs = std::filesystem;
using model::ExprGroup;
using NativeFn = ExprGroup::NativeFn;

struct State {
  std::mutex m;
  fs::path dir;
  std::string cc;
  // By the hash of a model's C source: one function per group (null for an empty group).
  std::unordered_map<std::string, std::vector<NativeFn>> loaded;
  std::unordered_map<std::string, std::string> failed;  // and why
  NativeStats stats;
};

State& state() {
  static State s;
  return s;
}

// FNV-1a, 64 bits, with the length: the cache's names and its check of a shared object's bytes.
std::string content_hash(std::string_view bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  std::ostringstream os;
  os << std::hex << h << "-" << std::dec << bytes.size();
  return os.str();
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The C of one model: the prelude, the helpers its expressions call, a function per group.
Expected<std::string> model_source(const std::vector<ExprGroup*>& groups,
                                   const model::Symbols& symbols) {
  std::string functions;
  std::set<std::string> helpers;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    if (groups[k]->empty()) continue;
    std::string unknown;
    codegen::CExprSet set(false, [&](const std::string& name) {
      const int slot = symbols.find(name);
      if (slot < 0) unknown = name;
      return "v[" + std::to_string(slot < 0 ? 0 : slot) + "]";
    });
    for (const auto& text : groups[k]->texts()) {
      if (auto i = set.add(text, "group " + std::to_string(k)); !i) return i.err();
    }
    if (!unknown.empty()) return Error{"no slot for the symbol '" + unknown + "'"};
    std::vector<std::string> texts;
    const std::string temps = set.emit("  ", texts);
    functions += "void kfw_g" + std::to_string(k) + "(const double *v, double *out) {\n" + temps;
    for (std::size_t i = 0; i < texts.size(); ++i)
      functions += "  out[" + std::to_string(i) + "] = " + texts[i] + ";\n";
    functions += "}\n\n";
    helpers.insert(set.helpers().begin(), set.helpers().end());
  }
  std::string s = "/* kfw native path: a model's expression groups (engine/native). */\n";
  s += "#include <math.h>\n\ntypedef double real;\n" + codegen::c_math_macros(false);
  s += "\n" + codegen::c_runtime(helpers);
  for (std::size_t k = 0; k < groups.size(); ++k) {
    if (!groups[k]->empty())
      s += "void kfw_g" + std::to_string(k) + "(const double *, double *);\n";
  }
  return s + "\n" + functions;
}

// Runs the compiler (no shell: the paths are arguments); its messages go to `log`.
Status compile(const std::string& cc, const fs::path& c, const fs::path& so, const fs::path& log) {
  std::vector<std::string> args = {cc,   "-O2",       "-ffp-contract=off", "-fPIC", "-shared",
                                   "-o", so.string(), c.string(),          "-lm"};
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, cc.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return Error{"cannot run the compiler '" + cc + "'"};
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::string first = slurp(log);
    first = first.substr(0, first.find('\n'));
    return Error{cc + " failed on " + c.string() + ": " + first};
  }
  return Ok{};
}

// The shared object for `source` from the cache (checked against the hash recorded when it was
// built) or built now; the group functions from it.
Expected<std::vector<NativeFn>> load(State& st, const std::string& key, const std::string& source,
                                     std::size_t groups) {
  const fs::path so = st.dir / (key + ".so"), sum = st.dir / (key + ".so.sum");
  bool cached = fs::exists(so) && fs::exists(sum) && slurp(sum) == content_hash(slurp(so));
  if (!cached) {
    const fs::path c = st.dir / (key + ".c"), log = st.dir / (key + ".log");
    const fs::path tmp = st.dir / (key + ".so." + std::to_string(::getpid()));
    { std::ofstream(c, std::ios::binary) << source; }
    if (auto r = compile(st.cc, c, tmp, log); !r) return r.err();
    { std::ofstream(sum, std::ios::binary) << content_hash(slurp(tmp)); }
    std::error_code ec;
    fs::rename(tmp, so, ec);
    if (ec) return Error{"cannot place " + so.string() + ": " + ec.message()};
    if (slurp(sum) != content_hash(slurp(so))) return Error{so.string() + ": changed while built"};
    ++st.stats.compiles;
  } else {
    ++st.stats.cache_loads;
  }
  void* handle = ::dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) return Error{std::string("dlopen: ") + ::dlerror()};
  std::vector<NativeFn> fns(groups, nullptr);
  for (std::size_t k = 0; k < groups; ++k) {
    void* f = ::dlsym(handle, ("kfw_g" + std::to_string(k)).c_str());
    fns[k] = reinterpret_cast<NativeFn>(f);  // null for an empty group
  }
  return fns;
}

// What makes a model's C: every group's texts and the symbols' slots (the generator is
// deterministic), so a model met again is attached without writing its C.
std::string inputs_key(const std::vector<ExprGroup*>& groups, const model::Symbols& symbols) {
  std::string k;
  for (const auto& n : symbols.names)
    k += n + '\x1f';
  for (const ExprGroup* g : groups) {
    k += '\x1e';
    for (const auto& t : g->texts())
      k += t + '\x1f';
  }
  return content_hash(k);
}

void attach(const std::vector<ExprGroup*>& groups, const model::Symbols& symbols) {
  State& st = state();
  const std::string inputs = inputs_key(groups, symbols);
  std::unique_lock lock(st.m);
  auto fallback = [&](const std::string& why) {
    st.stats.groups_fallback += groups.size();
    st.stats.last_error = why;
  };
  auto it = st.loaded.find(inputs);
  if (it == st.loaded.end()) {
    if (auto f = st.failed.find(inputs); f != st.failed.end()) return fallback(f->second);
    auto source = model_source(groups, symbols);
    auto fns = source ? load(st, content_hash(*source), *source, groups.size())
                      : Expected<std::vector<NativeFn>>(source.err());
    if (!fns) {
      st.failed.emplace(inputs, fns.error());
      return fallback(fns.error());
    }
    it = st.loaded.emplace(inputs, std::move(*fns)).first;
  }
  for (std::size_t k = 0; k < groups.size(); ++k) {
    if (groups[k]->empty()) continue;
    if (it->second[k]) {
      groups[k]->set_native(it->second[k]);
      ++st.stats.groups_native;
    } else {
      ++st.stats.groups_fallback;
    }
  }
}

fs::path default_cache_dir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "kfw";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "kfw";
  return fs::temp_directory_path() / ("kfw-cache-" + std::to_string(::getuid()));
}

}  // namespace

Status enable(const NativeOptions& options) {
  State& st = state();
  std::lock_guard lock(st.m);
  st.dir = options.cache_dir.empty() ? default_cache_dir() : fs::path(options.cache_dir);
  const char* cc_env = std::getenv("CC");
  st.cc = !options.compiler.empty() ? options.compiler : (cc_env && *cc_env ? cc_env : "cc");
  std::error_code ec;
  fs::create_directories(st.dir, ec);
  struct stat info {};
  if (::stat(st.dir.c_str(), &info) != 0 || !S_ISDIR(info.st_mode)) {
    return Error{"native: cannot make the cache folder " + st.dir.string()};
  }
  if (info.st_uid != ::getuid()) {
    return Error{"native: " + st.dir.string() + " belongs to another user; not using it"};
  }
  if ((info.st_mode & 0077) != 0 && ::chmod(st.dir.c_str(), 0700) != 0) {
    return Error{"native: cannot make " + st.dir.string() + " private (mode 0700)"};
  }
  model::set_expr_groups_hook(attach);
  return Ok{};
}

void disable() {
  model::set_expr_groups_hook({});
}

NativeStats stats() {
  State& st = state();
  std::lock_guard lock(st.m);
  return st.stats;
}

void forget() {
  State& st = state();
  std::lock_guard lock(st.m);
  st.loaded.clear();
  st.failed.clear();
}

std::string enable_from_environment() {
  const char* v = std::getenv("KFW_NATIVE");
  if (!v || std::string(v) != "1") return {};
  if (auto r = enable(); !r) return r.error() + "; expressions are evaluated by muparser";
  return {};
}

}  // namespace kfw::native
