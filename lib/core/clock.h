/* Clocks for the stages' timing lines in the log (--verbose): wall seconds and the process's
 * CPU seconds (all threads), so a log read on a loaded machine still shows the work done. */
#ifndef FR_CORE_CLOCK_H
#define FR_CORE_CLOCK_H

double fr_wall_seconds(void);
double fr_cpu_seconds(void);

/* A part's start, and its wall and CPU seconds since then. */
typedef struct fr_stopwatch {
    double wall, cpu;
} fr_stopwatch;

fr_stopwatch fr_stopwatch_start(void);
void fr_stopwatch_read(const fr_stopwatch *w, double *wall, double *cpu);

#endif
