// depthcull: depth-cull optimization of 2D scenes for 3D graphics hardware.
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>

#include "cli.h"
#include "depthcull/error.h"
#include "depthcull/io.h"

int main(int argc, char** argv) {
    // Past RLIMIT_FSIZE a write raises SIGXFSZ, which kills the run and
    // leaves its temporary; ignored, the write fails with EFBIG and the
    // run reports "OUT: write failed (File too large)" and cleans up.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{"depthcull: depth-cull optimization of 2D scenes for 3D graphics hardware"};
    app.name("depthcull");
    app.require_subcommand(1);
    app.set_version_flag("--version", "depthcull 0.1.0");
    app.footer("Exit status: 0 success, 1 an error in the input or output (one line on stderr naming the file), 2 a usage error.");
    depthcull::cli::add_analyze_command(app);
    depthcull::cli::add_optimize_command(app);
    depthcull::cli::add_render_command(app);
    depthcull::cli::add_bench_command(app);
    depthcull::cli::add_import_command(app);
    depthcull::cli::add_atlas_command(app);
    depthcull::cli::add_report_command(app);
    depthcull::cli::add_calibrate_command(app);
    for (int i = 0; i < argc; ++i) {
        // For reports: the command that made them, shell-quoted where needed.
        std::string arg = argv[i];
        bool plain = !arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=:,@+") == std::string::npos;
        depthcull::cli::g_command_line += (i ? " " : "") + (plain ? arg : "'" + arg + "'");
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version exit 0; every other CLI11 error is a usage
        // error, exit 2 (CLI11's own codes run 105-109), on one line as
        // every other error is (CLI11 prints two, without our prefix).
        if (e.get_exit_code() == 0) return app.exit(e);
        std::string what = e.what();
        for (char& c : what)
            if (c == '\n') c = ' ';
        const std::vector<CLI::App*> commands = app.get_subcommands();
        const std::string command = commands.empty() ? "depthcull" : "depthcull " + commands.front()->get_name();
        std::fprintf(stderr, "depthcull: error: %s (%s --help lists the options)\n", what.c_str(), command.c_str());
        return 2;
    } catch (const depthcull::cli::UsageError& e) {
        std::fprintf(stderr, "depthcull: error: %s\n", e.what());
        return 2;
    } catch (const std::bad_alloc&) {
        // Outside every reader's guard (which names its file): name the
        // command, so the line still says what was being read.
        std::fprintf(stderr, "depthcull: error: %s: out of memory (the limits allow %llu MiB of decoded images, kMaxDecodedBytes, and %llu MiB of analysis memory, kMaxAnalysisBytes)\n",
                     depthcull::cli::g_command_line.c_str(), static_cast<unsigned long long>(depthcull::limits::kMaxDecodedBytes >> 20),
                     static_cast<unsigned long long>(depthcull::kMaxAnalysisBytes >> 20));
        return 1;
    } catch (const depthcull::Error& e) {
        // io's, the pipeline's, the GL renderer's (render::Error) and the
        // commands' (CliError): one line naming the file.
        std::fprintf(stderr, "depthcull: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        // Anything unforeseen (a library's own type): the same one line.
        std::fprintf(stderr, "depthcull: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
