#include "runtime/api/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

namespace crex {
namespace {

// The first stopping signal that arrived (SIGINT or SIGTERM), 0 before one has.
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "set from a signal handler");

// Async-signal-safe: an atomic exchange, write(2), and at the second signal the default action.
void on_stop_signal(int signal) {
    if (g_signal.exchange(signal) != 0) {
        std::signal(signal, SIG_DFL);
        std::raise(signal);  // delivered once the handler returns: the process ends as killed by it
        return;
    }
    static const char kCtrlC[] =
        "\ncrex: interrupted: stopping after the pass in flight (Ctrl-C again to quit now)\n";
    static const char kTerm[] =
        "\ncrex: interrupted by SIGTERM: stopping after the pass in flight (a second signal quits now)\n";
    const ssize_t ignored = signal == SIGTERM ? ::write(STDERR_FILENO, kTerm, sizeof kTerm - 1) : ::write(STDERR_FILENO, kCtrlC, sizeof kCtrlC - 1);
    (void)ignored;
}

}  // namespace

void catch_interrupt() {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

bool interrupted() { return g_signal.load() != 0; }

int interrupted_exit_code() {
    const int signal = g_signal.load();
    return 128 + (signal != 0 ? signal : SIGINT);
}

}  // namespace crex
