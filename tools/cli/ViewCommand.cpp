// `strata view RECORDING --out DIR [--serve [--port N] [--serve-seconds S]]`: the browser viewer of a
// recorded demo or simulate run (`--record FILE`): writes the folder (tools/view/ViewerFolder.h) and, with
// --serve, serves it on 127.0.0.1. A bad recording or folder exits with code 2 and writes nothing.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "tools/cli/Commands.h"
#include "tools/cli/Validators.h"
#include "tools/view/Recording.h"
#include "tools/view/StaticFileServer.h"
#include "tools/view/ViewerFolder.h"

namespace strata::cli {

namespace {

struct ViewOptions {
  std::string recording;
  std::string out = "build/view";
  bool serve = false;
  int port = 8080;
  double serve_seconds = 0.0;
};

int RunView(const ViewOptions& options) {
  Result<nlohmann::json> recording = view::ReadRecording(options.recording);
  if (!recording) {
    std::cerr << "strata view: " << recording.error().message << "\n";
    return 2;
  }
  Result<view::ViewerFolderSummary> written = view::WriteViewerFolder(*recording, options.out);
  if (!written) {
    std::cerr << "strata view: " << written.error().message << "\n";
    return 2;
  }
  std::printf(
      "wrote %s/index.html: %zu level triangles, %zu navmesh triangles in %zu island colours, %zu bodies, "
      "%zu "
      "agents, %zu tiles, %zu frames\n",
      options.out.c_str(), written->level_triangles, written->navmesh_triangles,
      written->navmesh_colours.size(), written->bodies, written->agents, written->tiles, written->frames);
  std::fflush(stdout);
  if (!options.serve) return 0;
  view::ServeOptions serve;
  serve.port = options.port;
  serve.duration = std::chrono::milliseconds(static_cast<std::int64_t>(options.serve_seconds * 1000.0));
  serve.on_listening = [&](int port) {
    std::printf("serving %s at http://127.0.0.1:%d/ (Ctrl-C stops)\n", options.out.c_str(), port);
    std::fflush(stdout);
  };
  if (Status served = view::ServeFolder(options.out, serve); !served) {
    std::cerr << "strata view: " << served.message() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace

std::function<int()> AddViewCommand(CLI::App& app) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* command = app.add_subcommand(
      "view",
      "write a recorded run (demo/simulate --record) as a browser page; --serve shows it on localhost");
  command->add_option("recording", options->recording, "the file demo or simulate wrote with --record")
      ->required();
  command
      ->add_option("--out", options->out, "the folder to write (index.html, viewer.js, data.js, scene.glb)")
      ->capture_default_str();
  command->add_flag("--serve", options->serve, "serve the folder on 127.0.0.1 after writing it");
  command->add_option("--port", options->port, "port to serve on (0: any free one)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  command
      ->add_option("--serve-seconds", options->serve_seconds, "stop serving after this long (0: at Ctrl-C)")
      ->check(FiniteIn(0.0, 1.0e7))
      ->capture_default_str();
  return [options] { return RunView(*options); };
}

}  // namespace strata::cli
