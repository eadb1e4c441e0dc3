// NAME_example.c (c_export_detail.h): reads a CSV in kfw's format — a header, then t, the inputs
// and the channels' roles as columns — runs the exported filter row by row as kfw runs it, and
// writes t, x and the upper triangle of P under the column names of `kfw-cli run --out`. The
// clock is the caller's, shown here: the inputs' last finite values held, a channel updated on
// rows k with k % every == 0 where every role has a value.
#include <algorithm>

#include "codegen/c_export_detail.h"

namespace kfw::codegen::detail {

namespace {

const char* kHelpers = R"C(#define LINE_CHARS 65536
#define MAX_FIELDS 1024

/* Splits a line at commas in place (its line end removed); the number of fields, -1 when more
   than MAX_FIELDS. */
static int split(char *line, char **field) {
  int n = 0;
  size_t len = strlen(line);
  char *p;
  while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = '\0';
  field[n++] = line;
  for (p = line; *p; ++p) {
    if (*p != ',') continue;
    *p = '\0';
    if (n == MAX_FIELDS) return -1;
    field[n++] = p + 1;
  }
  return n;
}

/* Field i of a row as a number: NaN when absent, empty or not a number. */
static double value_of(char **field, int n, int i) {
  const char *f;
  char *end;
  double v;
  if (i < 0 || i >= n) return NAN;
  f = field[i];
  while (*f == ' ') ++f;
  if (!*f) return NAN;
  v = strtod(f, &end);
  return end == f ? NAN : v;
}

static int column(char **field, int n, const char *name) {
  int i;
  for (i = 0; i < n; ++i) {
    if (strcmp(field[i], name) == 0) return i;
  }
  return -1;
}

/* A line, or 0 at the end; exits with 2 on a line longer than LINE_CHARS. */
static char *read_line(char *line, FILE *in, const char *path) {
  if (!fgets(line, LINE_CHARS, in)) return 0;
  if (!strchr(line, '\n') && !feof(in)) {
    fprintf(stderr, "%s: a line longer than %d characters\n", path, LINE_CHARS - 1);
    exit(2);
  }
  return line;
}

static int require(int col, const char *path, const char *name) {
  if (col < 0) {
    fprintf(stderr, "%s: no column '%s'\n", path, name);
    exit(2);
  }
  return col;
}

)C";

std::string quoted_c(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += (static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
  }
  return q + "\"";
}

std::string output_header(const Gen& g) {
  std::string h = "t";
  for (const auto& st : g.spec.states)
    h += ",x." + st.name;
  if (g.steady()) return h;
  for (int i = 0; i < g.n; ++i) {
    for (int j = i; j < g.n; ++j) {
      const auto& a = g.spec.states[static_cast<std::size_t>(i)].name;
      const auto& b = g.spec.states[static_cast<std::size_t>(j)].name;
      h += ",P." + a + (i == j ? "" : "." + b);
    }
  }
  for (const auto& m : g.mode_names)
    h += ",mu." + m;
  return h;
}

// The rows: predict, the inputs held, each channel updated when its clock and its sample allow,
// the estimates written.
// "ready = ..." lines: channel ch's raw sample read into z, ready when its clock allows, every role
// has a value and no missing flag marks it.
std::string channel_sample(const Gen& g, std::size_t ch) {
  const auto& cs = g.spec.channels[ch];
  const std::string M = c_macro(g.P), name = c_name(cs.name);
  std::string c = "      ready = k % " + M + "_EVERY_" + c_macro(cs.name) + " == 0;\n" +
                  "      for (j = 0; j < " + std::to_string(cs.roles.size()) + "; ++j) {\n" +
                  "        const double v = value_of(field, n, col_" + name + "[j]);\n" +
                  "        if (!isfinite(v)) ready = 0;\n        z[j] = (" + g.P + "_real)v;\n" +
                  "      }\n";
  if (g.missing_on[ch]) {
    c += "      if (ready && value_of(field, n, col_missing_" + name + ") == " + M + "_MISSING_" +
         c_macro(cs.name) + ") ready = 0; /* flagged missing */\n";
  }
  return c;
}

// The group (index) whose instant channel ch's samples wait for, and ch's index among its
// members; -1 when it updates on its own.
std::pair<int, int> waiting_group(const Gen& g, std::size_t ch) {
  for (std::size_t k = 0; k < g.spec.groups.size(); ++k) {
    if (g.ev.group(k).scheme == model::GroupScheme::kEach) continue;
    const auto& m = g.spec.groups[k].members;
    for (std::size_t a = 0; a < m.size(); ++a) {
      if (m[a] == static_cast<int>(ch)) return {static_cast<int>(k), static_cast<int>(a)};
    }
  }
  return {-1, -1};
}

// flush_GROUP: the waiting samples at their instant — the stacked update, or the members' own
// updates one after the other.
std::string group_flushes(const Gen& g) {
  std::string c;
  const std::string R = g.P + "_real", M = c_macro(g.P);
  for (std::size_t k = 0; k < g.spec.groups.size(); ++k) {
    const auto scheme = g.ev.group(k).scheme;
    if (scheme == model::GroupScheme::kEach) continue;
    const auto& gs = g.spec.groups[k];
    const std::string gn = c_name(gs.name), step = group_reads_step(g, k) ? "u, t, " : "";
    c += "/* Group " + comment_text(gs.name) + "'s waiting samples at their instant. */\n";
    c += "static int flush_" + gn + "(" + g.P + "_state *s, int *n, const int m[], const " + R +
         " z[]" + (step.empty() ? "" : ", const " + R + " *u, " + R + " t") + ") {\n  " + R +
         " nis[" + std::to_string(gs.members.size()) + "];\n  int r = 0, i;\n  (void)i;\n";
    if (scheme == model::GroupScheme::kStacked) {
      c += "  if (*n > 0) r = " + g.P + "_update_" + gn + "(s, *n, m, z, " + step + "nis);\n";
    } else {
      c += "  for (i = 0; i < *n && r != " + M + "_DIVERGED; ++i) {\n    switch (m[i]) {\n";
      for (std::size_t a = 0; a < gs.members.size(); ++a) {
        const auto& ch = g.spec.channels[static_cast<std::size_t>(gs.members[a])];
        c += "      case " + std::to_string(a) + ":\n        r = " + g.P + "_update_" +
             c_name(ch.name) + "(s, &z[i], " + (channel_reads_step(ch) ? "u, t, " : "") +
             "nis);\n        break;\n";
      }
      c += "      default:\n        break;\n    }\n  }\n";
    }
    c += "  *n = 0;\n  if (r == " + M +
         "_DIVERGED) fprintf(stderr, \"the filter diverged\\n\");\n"
         "  return r;\n}\n\n";
  }
  return c;
}

std::string example_loop(const Gen& g) {
  const model::ModelSpec& s = g.spec;
  const std::string M = c_macro(g.P), fmt = g.opt.single ? "%.9g" : "%.17g";
  std::string c;
  c += "  while (read_line(line, in, path)) {\n    n = split(line, field);\n"
       "    if (n <= 1 && field[0][0] == '\\0') continue; /* a blank line */\n"
       "    t = value_of(field, n, col_t);\n";
  if (g.ages) {  // each input's age: the time since its last sample, from the first row on
    c += "    for (j = 0; j < " + M +
         "_NU; ++j) {\n      if (k == 0) u_time[j] = t;\n"
         "      u[" +
         M + "_NU + j] = (" + g.P + "_real)(t_prev - u_time[j]);\n    }\n";
  }
  c += "    if (k0 >= 0 && k > k0 && (r = " + g.P + "_predict(&s, u, (" + g.P + "_real)t_prev, (" +
       g.P +
       "_real)(t - t_prev))) < 0) {\n"
       "      fprintf(stderr, \"%s: row %ld: the filter diverged\\n\", path, k);\n      return 1;\n"
       "    }\n";
  if (g.nu > 0) {
    c += "    for (j = 0; j < " + M +
         "_NU; ++j) { /* the inputs' last finite values held */\n"
         "      const double v = value_of(field, n, col_u[j]);\n      if (isfinite(v)) {\n"
         "        u[j] = (" +
         g.P + "_real)v;\n" + (g.ages ? "        u_time[j] = t;\n" : "") + "      }\n    }\n";
    if (g.ages) {
      c += "    for (j = 0; j < " + M + "_NU; ++j) u[" + M + "_NU + j] = (" + g.P +
           "_real)(t - u_time[j]);\n";
    }
  }
  if (s.start_channel >= 0) {  // x0 from the channel's first sample: the filter starts there
    const auto sc = static_cast<std::size_t>(s.start_channel);
    const auto& cs = s.channels[sc];
    c += "    if (k0 < 0) {\n" + channel_sample(g, sc) + "      if (ready) {\n        if (!" + g.P +
         "_init_from_" + c_name(cs.name) + "(&s, z" +
         (channel_reads_step(cs) ? ", u, (" + g.P + "_real)t" : "") +
         ")) {\n          fprintf(stderr, \"%s: row %ld: the first sample of channel " +
         comment_text(cs.name) +
         " makes no x0\\n\", path, k);\n          return 1;\n        }\n"
         "        k0 = k;\n      }\n    }\n";
    c += "    if (k0 < 0) { /* before the filter starts: no estimate */\n      fprintf(out, \"" +
         fmt +
         "\", (double)t);\n      for (j = 1; j < columns; ++j) fputc(',', out);\n"
         "      fputc('\\n', out);\n      t_prev = t;\n      ++k;\n      continue;\n    }\n";
  }
  for (std::size_t ch = 0; ch < s.channels.size(); ++ch) {
    const auto& cs = s.channels[ch];
    const std::string name = c_name(cs.name);
    const bool start = static_cast<int>(ch) == s.start_channel;
    c += std::string(start ? "    if (k > k0) {\n" : "    {\n") + channel_sample(g, ch);
    if (const auto [k, a] = waiting_group(g, ch); k >= 0) {
      const auto& gs = s.groups[static_cast<std::size_t>(k)];
      const std::string gn = c_name(gs.name), gm = std::to_string(gs.members.size()),
                        aa = std::to_string(a);
      const std::string flush =
          "flush_" + gn + "(&s, &pn_" + gn + ", pm_" + gn + ", pz_" + gn +
          (group_reads_step(g, static_cast<std::size_t>(k)) ? ", u, (" + g.P + "_real)t" : "") +
          ") == " + M + "_DIVERGED";
      c += "      if (ready) { /* the sample waits for its group's instant */\n"
           "        for (i = 0; i < pn_" +
           gn + "; ++i) {\n          if (pm_" + gn + "[i] == " + aa +
           ") { /* a sample repeats: the instant closes before it */\n            if (" + flush +
           ") return 1;\n            break;\n          }\n        }\n        pm_" + gn + "[pn_" +
           gn + "] = " + aa + ";\n        pz_" + gn + "[pn_" + gn + "++] = z[0];\n        if (pn_" +
           gn + " == " + gm + " && " + flush + ") return 1;\n      }\n    }\n";
      continue;
    }
    c += "      if (ready && (r = " + g.P + "_update_" + name + "(&s, z, " +
         (channel_reads_step(cs) ? "u, (" + g.P + "_real)t, " : "") + "&nis)) == " + M +
         "_DIVERGED) {\n"
         "        fprintf(stderr, \"%s: row %ld: the filter diverged\\n\", path, k);\n"
         "        return 1;\n      }\n    }\n";
  }
  c += "    fprintf(out, \"" + fmt + "\", (double)t);\n";
  c += "    for (j = 0; j < " + M + "_N; ++j) fprintf(out, \"," + fmt + "\", (double)s.x[j]);\n";
  if (!g.steady()) {
    c += "    for (j = 0; j < " + M + "_N; ++j) {\n      int i;\n      for (i = j; i < " + M +
         "_N; ++i) fprintf(out, \"," + fmt + "\", (double)s.P[j][i]);\n    }\n";
  }
  if (g.modes > 0) {
    c += "    for (j = 0; j < " + M + "_MODES; ++j) fprintf(out, \"," + fmt +
         "\", (double)s.mu[j]);\n";
  }
  c += "    fprintf(out, \"\\n\");\n    t_prev = t;\n    ++k;\n  }\n";
  c += "  (void)i;\n  (void)nis;\n  (void)r;\n  (void)ready;\n  (void)col_u;\n  (void)z;\n  "
       "fclose(in);\n"
       "  if (out != stdout && fclose(out) != 0) {\n    fprintf(stderr, \"%s: cannot write\\n\", "
       "out_path);\n    return 1;\n  }\n  return 0;\n}\n";
  return c;
}

}  // namespace

std::string example_program(const Gen& g) {
  const model::ModelSpec& s = g.spec;
  const std::string M = c_macro(g.P), fmt = g.opt.single ? "%.9g" : "%.17g";
  std::string c = "/* " + g.P + "_example.c: runs " + g.P +
                  ".c over a CSV in kfw's format and writes "
                  "the estimates\n   as CSV, the columns of kfw-cli run --out. Build and run:\n"
                  "     cc -std=c99 -O2 " +
                  g.P + ".c " + g.P + "_example.c -lm -o " + g.P + "_example\n     ./" + g.P +
                  "_example DATA.csv [ESTIMATES.csv]\n"
                  "   exported by kfw " KFW_VERSION " from " +
                  comment_text(g.opt.preset) + ". */\n";
  c += std::string("#include <math.h>\n") + (g.rt() ? "#include <stddef.h>\n" : "") +
       "#include <stdio.h>\n#include <stdlib.h>\n#include <string.h>\n\n";
  c += "#include \"" + g.P + ".h\"\n\n" + kHelpers + group_flushes(g);
  // The x0 columns read from their first finite sample.
  std::vector<std::string> firsts;
  for (const auto& x0 : s.x0) {
    if (!x0.first_column.empty() &&
        std::find(firsts.begin(), firsts.end(), x0.first_column) == firsts.end())
      firsts.push_back(x0.first_column);
  }
  c += "int main(int argc, char **argv) {\n  static char line[LINE_CHARS];\n"
       "  char *field[MAX_FIELDS];\n  const char *path;\n  FILE *in, *out;\n  " +
       g.P + "_state s;\n  " + (g.ages ? "double u_time[" + std::to_string(g.nu) + "];\n  " : "") +
       g.P + "_real u[" + std::to_string(std::max(g.ages ? 2 * g.nu : g.nu, 1)) + "] = {0}, z[" +
       std::to_string(g.roles_max) +
       "], nis;\n"
       "  double t, t_prev = 0; /* in double: a float time loses the interval (7.6e-6 s at 100 s) "
       "*/\n"
       "  long k = 0, k0 = " +
       (s.start_channel >= 0 ? "-1" : "0") +
       "; /* the row the filter starts at */\n  int n, col_t, i, j, ready, r;\n";
  for (std::size_t k = 0; k < s.groups.size(); ++k) {
    if (g.ev.group(k).scheme == model::GroupScheme::kEach) continue;
    const std::string gn = c_name(s.groups[k].name),
                      gm = std::to_string(s.groups[k].members.size());
    c += "  int pn_" + gn + " = 0, pm_" + gn + "[" + gm + "]; /* group " +
         comment_text(s.groups[k].name) + ": the samples waiting */\n  " + g.P + "_real pz_" + gn +
         "[" + gm + "];\n";
  }
  if (s.start_channel >= 0) {
    const std::string h = output_header(g);
    c += "  const int columns = " + std::to_string(std::count(h.begin(), h.end(), ',') + 1) + ";\n";
  }
  c += "  int col_u[" + std::to_string(std::max(g.nu, 1)) + "] = {-1};\n";
  for (std::size_t ch = 0; ch < s.channels.size(); ++ch)
    c += "  int col_" + c_name(s.channels[ch].name) + "[" + std::to_string(s.channels[ch].size()) +
         "];\n";
  for (std::size_t f = 0; f < firsts.size(); ++f)
    c += "  int col_first" + std::to_string(f) + ";\n  double first" + std::to_string(f) +
         " = NAN;\n";
  for (std::size_t ch = 0; ch < s.channels.size(); ++ch) {
    if (g.missing_on[ch]) c += "  int col_missing_" + c_name(s.channels[ch].name) + ";\n";
  }
  c += "  const char *out_path = 0;\n";
  if (g.rt()) {
    c += "  " + g.P +
         "_params p;\n  static const struct {\n    const char *key;\n"
         "    size_t offset;\n  } keys[] = {";
    bool first = true;
    for (const auto& [name, v] : g.consts) {
      c += std::string(first ? "" : ",") + "\n      {" + quoted_c(name.substr(4)) + ", offsetof(" +
           g.P + "_params, " + name + ")}";
      first = false;
    }
    if (first) c += "{\"\", 0}";
    c += "};\n";
  }
  c += "  if (argc < 2) {\n    fprintf(stderr, \"usage: %s DATA.csv [ESTIMATES.csv]" +
       std::string(g.rt() ? " [KEY=VALUE]..." : "") +
       "\\n\", argv[0]);\n    return 2;\n  }\n"
       "  path = argv[1];\n";
  if (g.rt()) {  // KEY=VALUE: a parameter's value instead of the exported one
    c += "  " + g.P + "_params_default(&p);\n";
    c += "  for (i = 2; i < argc; ++i) {\n    const char *eq = strchr(argv[i], '=');\n"
         "    size_t a;\n    if (!eq) {\n      out_path = argv[i];\n      continue;\n    }\n"
         "    for (a = 0; a < sizeof keys / sizeof keys[0]; ++a) {\n"
         "      if (strlen(keys[a].key) == (size_t)(eq - argv[i]) && "
         "strncmp(keys[a].key, argv[i], (size_t)(eq - argv[i])) == 0) break;\n    }\n"
         "    if (a == sizeof keys / sizeof keys[0]) {\n      fprintf(stderr, \"%s: no parameter "
         "of that name\\n\", argv[i]);\n      return 2;\n    }\n"
         "    *(" +
         g.P + "_real *)((char *)&p + keys[a].offset) = (" + g.P +
         "_real)strtod(eq + 1, 0);\n  }\n";
  } else {
    c += "  if (argc > 3) {\n    fprintf(stderr, \"usage: %s DATA.csv [ESTIMATES.csv]\\n\", "
         "argv[0]);\n    return 2;\n  }\n  if (argc == 3) out_path = argv[2];\n";
  }
  c += "  in = fopen(path, \"r\");\n  if (!in) {\n    fprintf(stderr, \"%s: cannot open\\n\", "
       "path);\n    return 2;\n  }\n";
  c += "  if (!read_line(line, in, path) || (n = split(line, field)) < 0) {\n"
       "    fprintf(stderr, \"%s: no header\\n\", path);\n    return 2;\n  }\n";
  c += "  col_t = require(column(field, n, \"t\"), path, \"t\");\n";
  for (int i = 0; i < g.nu; ++i) {
    const auto q = quoted_c(s.inputs[static_cast<std::size_t>(i)].name);
    c += "  col_u[" + std::to_string(i) + "] = require(column(field, n, " + q + "), path, " + q +
         ");\n";
  }
  for (const auto& ch : s.channels) {
    for (std::size_t j = 0; j < ch.roles.size(); ++j) {
      const auto q = quoted_c(ch.roles[j].name);
      c += "  col_" + c_name(ch.name) + "[" + std::to_string(j) + "] = require(column(field, n, " +
           q + "), path, " + q + ");\n";
    }
  }
  for (std::size_t f = 0; f < firsts.size(); ++f)
    c += "  col_first" + std::to_string(f) + " = column(field, n, " + quoted_c(firsts[f]) + ");\n";
  for (std::size_t ch = 0; ch < s.channels.size(); ++ch) {
    if (!g.missing_on[ch]) continue;
    c += "  col_missing_" + c_name(s.channels[ch].name) + " = column(field, n, " +
         quoted_c(s.channels[ch].missing.column) + "); /* none: nothing flagged */\n";
  }
  if (!firsts.empty()) {
    c += "  /* x0: the first finite sample of each x0 column (kfw's rule). */\n";
    c += "  while (read_line(line, in, path)) {\n    n = split(line, field);\n";
    for (std::size_t f = 0; f < firsts.size(); ++f) {
      const std::string v = "first" + std::to_string(f);
      std::string flagged;  // a channel reading this column flags the row missing
      for (std::size_t ch = 0; ch < s.channels.size(); ++ch) {
        if (!g.missing_on[ch]) continue;
        for (const auto& r : s.channels[ch].roles) {
          if (r.name != firsts[f]) continue;
          flagged += " && value_of(field, n, col_missing_" + c_name(s.channels[ch].name) +
                     ") != " + M + "_MISSING_" + c_macro(s.channels[ch].name);
        }
      }
      c += "    if (!isfinite(" + v + ")" + flagged + ") " + v + " = value_of(field, n, col_first" +
           std::to_string(f) + ");\n";
    }
    c += "  }\n  rewind(in);\n  (void)read_line(line, in, path);\n";
  }
  c += "  " + g.P + "_init(&s" + (g.rt() ? ", &p" : "") + ");\n";
  for (std::size_t f = 0; f < firsts.size(); ++f) {
    const std::string v = "first" + std::to_string(f);
    c += "  if (isfinite(" + v + ")) " + g.P + "_init_from_" + c_name(firsts[f]) + "(&s, (" + g.P +
         "_real)" + v + ");\n";
  }
  c += "  if (out_path && strcmp(out_path, path) == 0) {\n    fprintf(stderr, \"%s: the estimates "
       "would overwrite the data\\n\", path);\n    return 2;\n  }\n";
  c += "  out = out_path ? fopen(out_path, \"w\") : stdout;\n  if (!out) {\n    fprintf(stderr, "
       "\"%s: cannot write\\n\", out_path);\n    return 2;\n  }\n";
  c += "  fputs(" + quoted_c(output_header(g)) + ", out);\n  fputs(\"\\n\", out);\n";
  c += example_loop(g);
  return c;
}

}  // namespace kfw::codegen::detail
