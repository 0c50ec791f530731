/// \file guarded_rendering.h
/// How `crex run` and `crex reference` turn a failed render into an exit status.
#pragma once

#include <exception>
#include <iostream>
#include <string_view>
#include <type_traits>

#include "base/check.h"
#include "base/exit_codes.h"
#include "runtime/api/console_progress.h"
#include "runtime/driver/run_settings.h"

namespace crex::app {

/// Runs `render` (it may return an exit status) and says why it failed, as `COMMAND: error:`:
/// a bug goes on to main, which says so; input the render cannot use is exit 1, anything else
/// 3. The progress line is cleared either way, so the message starts a line of its own.
template <class Render>
int guarded_rendering(std::string_view command, ConsoleProgress& progress, Render&& render) {
    int status = kExitOk;
    try {
        if constexpr (std::is_void_v<std::invoke_result_t<Render&>>) render();
        else status = render();
    } catch (const InternalError&) {
        progress.finish();
        throw;
    } catch (const RunInputError& e) {
        progress.finish();
        std::cerr << command << ": error: " << e.what() << "\n";
        return kExitInputErrors;
    } catch (const std::exception& e) {
        progress.finish();
        std::cerr << command << ": error: rendering failed: " << e.what() << "\n";
        return kExitFailure;
    }
    progress.finish();
    return status;
}

}  // namespace crex::app
