/* s51_fastpoll.c — preloaded into s51 by the firmware tests (LD_PRELOAD).
 * A stopped s51 looks at its console, finds no command yet and sleeps
 * 100 ms (nanosleep, seen with strace) before it looks again, so every
 * command of a test that waits for each answer costs ~100 ms: minutes for
 * a run that needs seconds.  Here that sleep ends as soon as the console
 * (its standard input) has a command to read, and is still a sleep, not a
 * busy loop, while it has none.  s51 sleeps nowhere else; what it
 * simulates and counts does not change, only how soon it hears the next
 * command.  Built without the project's EXTRA_CFLAGS: a sanitizer's
 * runtime cannot be preloaded into s51. */
#include <poll.h>
#include <time.h>

int nanosleep(const struct timespec *req, struct timespec *rem)
{
    struct pollfd console = {0, POLLIN, 0};
    long ms = (long)req->tv_sec * 1000 + req->tv_nsec / 1000000;
    if (rem)
        rem->tv_sec = rem->tv_nsec = 0;
    if (poll(&console, 1, (int)(ms > 0 ? ms : 1)) < 0)
        return -1;
    return 0;
}
