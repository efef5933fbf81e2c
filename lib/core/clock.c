/* Wall and CPU clocks for the stages' timing lines (core/clock.h). */
#include <time.h>

#include "core/clock.h"

static double seconds_of(clockid_t id) {
    struct timespec ts;
    if (clock_gettime(id, &ts)) return 0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double fr_wall_seconds(void) { return seconds_of(CLOCK_MONOTONIC); }

double fr_cpu_seconds(void) { return seconds_of(CLOCK_PROCESS_CPUTIME_ID); }

fr_stopwatch fr_stopwatch_start(void) {
    fr_stopwatch w = {fr_wall_seconds(), fr_cpu_seconds()};
    return w;
}

void fr_stopwatch_read(const fr_stopwatch *w, double *wall, double *cpu) {
    if (wall) *wall = fr_wall_seconds() - w->wall;
    if (cpu) *cpu = fr_cpu_seconds() - w->cpu;
}
