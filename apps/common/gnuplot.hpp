#pragma once
// Plots through gnuplot, written completely or not at all: data files, the script and the images
// are made in a hidden temporary folder beside the target and only the finished images move into
// place. A signal handler can stop a running gnuplot (stop_gnuplot) before the temporaries go.

#include <filesystem>
#include <functional>
#include <string>

namespace sets::app {

/// 'text' quoted for a gnuplot script (single quotes doubled).
std::string gnuplot_quote(const std::string& text);

/// Runs `gnuplot script` with its messages in `log`; InputError with gnuplot's messages when it
/// fails or cannot be started.
void run_gnuplot(const std::filesystem::path& script, const std::filesystem::path& log);

/// Kills a running gnuplot. Async-signal-safe.
void stop_gnuplot() noexcept;

/// One PNG: `script(work, png)` writes its data files into the folder `work` and returns the
/// plotting commands, which must write `png` (a file inside `work`); the terminal line comes from
/// `terminal`. The finished image is renamed to `target`. Throws InputError.
void render_png(const std::string& target, const std::string& terminal,
                const std::function<std::string(const std::filesystem::path& work, const std::string& png)>& script);

}  // namespace sets::app
