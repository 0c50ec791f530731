#include "runtime/api/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

namespace crex {
namespace {

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

// Async-signal-safe: an atomic store, write(2), and at the second SIGINT the default action.
void on_interrupt(int) {
    if (g_interrupted.exchange(true)) {
        std::signal(SIGINT, SIG_DFL);
        std::raise(SIGINT);  // delivered once the handler returns: the process ends as killed by SIGINT
        return;
    }
    static const char kSaid[] =
        "\ncrex: interrupted: finishing the pass in flight, then writing the image so far (Ctrl-C again to quit now)\n";
    const ssize_t ignored = ::write(STDERR_FILENO, kSaid, sizeof kSaid - 1);
    (void)ignored;
}

}  // namespace

void catch_interrupt() {
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(SIGINT, &action, nullptr);
}

bool interrupted() { return g_interrupted.load(); }

}  // namespace crex
