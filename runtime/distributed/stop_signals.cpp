#include "runtime/distributed/stop_signals.h"

#include <pthread.h>
#include <unistd.h>

#include <csignal>
#include <thread>

namespace crex::distributed {
namespace {

sigset_t stop_set() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGHUP);
    return set;
}

// What the signal would have done without take_stop_signals: this thread alone unblocks it
// and sends it to itself, with the default action (ends the process).
[[noreturn]] void default_action(int signal) {
    std::signal(signal, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, signal);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    std::raise(signal);
    for (;;) pause();  // the signal is delivered on return from raise; nothing carries on
}

}  // namespace

void take_stop_signals(void (*on_stop)(int signal)) {
    const sigset_t set = stop_set();
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    // Detached: it lives as long as the process, and exit() does not wait for it.
    std::thread([set, on_stop] {
        int signal = 0;
        while (sigwait(&set, &signal) != 0) {
        }
        on_stop(signal);
        default_action(signal);
    }).detach();
}

}  // namespace crex::distributed
