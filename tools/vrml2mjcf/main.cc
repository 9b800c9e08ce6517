// ohrp_vrml2mjcf: prints or writes the MJCF made from an OpenHRP VRML file (vrml/vrml.h), after
// checking that MuJoCo loads it; or a one-line summary of the model.
#include <cstdio>
#include <fstream>
#include <string>

#include "cli/command_line.h"
#include "vrml/vrml.h"

int main(int argc, char** argv) {
  std::string input, output, print = "mjcf";
  CLI::App app{
      "ohrp_vrml2mjcf: the MJCF that sim_host, hw_driver, hw_emulator and the robot-model library\n"
      "make in memory from an OpenHRP VRML97 file (.wrl: Humanoid, Joint, Segment, sensors; Inline\n"
      "files joined), checked by loading it in MuJoCo, to read or to edit by hand. What the\n"
      "conversion does: docs/vrml.md."};
  app.add_option("wrl", input, "OpenHRP VRML file (e.g. ../shared/external/openhrp3-sample/sample1.wrl)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-o,--output", output, "MJCF file to write (default: standard output)");
  app.add_option("--print", print, "mjcf: the MJCF text; summary: one line of counts")
      ->check(CLI::IsMember({"mjcf", "summary"}))
      ->capture_default_str();
  app.footer(
      "Exit codes: 0 done, 1 the output could not be written, 2 bad option, a VRML file that\n"
      "cannot be read or converted (file:line:column: what) or an MJCF MuJoCo refuses.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;

  // convert, then load: what is written is what the platform loads
  std::string mjcf, error;
  if (!ohrp::vrml::ConvertFile(input, &mjcf, &error)) {
    std::fprintf(stderr, "ohrp_vrml2mjcf: %s\n", error.c_str());
    return 2;
  }
  mjModel* m = ohrp::vrml::LoadModel(input, &error);
  if (!m) {
    std::fprintf(stderr, "ohrp_vrml2mjcf: %s\n", error.c_str());
    return 2;
  }
  std::string text = mjcf;
  if (print == "summary") {
    double mass = 0;
    for (int b = 1; b < m->nbody; ++b) mass += m->body_mass[b];
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s: %d bodies, %d joints, %d motors, %d sensors, %d geoms, %d keyframes, %.6f kg\n",
                  input.c_str(), m->nbody - 1, m->njnt, m->nu, m->nsensor, m->ngeom, m->nkey, mass);
    text = line;
  }
  mj_deleteModel(m);

  // write
  if (output.empty()) {
    std::fputs(text.c_str(), stdout);
    return 0;
  }
  std::ofstream out(output, std::ios::binary);
  out << text;
  if (!out.flush()) {
    std::fprintf(stderr, "ohrp_vrml2mjcf: cannot write '%s'\n", output.c_str());
    return 1;
  }
  return 0;
}
