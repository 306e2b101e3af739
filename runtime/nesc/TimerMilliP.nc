/* TimerMilliP.nc - the millisecond timers of every TimerMilliC, driven by Clock.advance:
 * due timers are signalled from one task, in the order of their numbers. */
module TimerMilliP {
    provides interface Timer<TMilli> as Timer[uint8_t id];
    provides interface Clock;
}
implementation {
    enum { N_TIMERS = uniqueCount("TimerMilliC.Timer") };

    bool running[N_TIMERS];
    bool periodic[N_TIMERS];
    bool due[N_TIMERS];
    uint32_t period[N_TIMERS];
    uint32_t remaining[N_TIMERS];

    task void fireDue() {
        uint8_t id;
        for (id = 0; id < N_TIMERS; id++) {
            if (due[id]) {
                due[id] = FALSE;
                signal Timer.fired[id]();
            }
        }
    }

    void start(uint8_t id, uint32_t dt, bool repeat) {
        if (id >= N_TIMERS) {
            return;
        }
        running[id] = TRUE;
        periodic[id] = repeat;
        period[id] = dt;
        remaining[id] = dt;
    }

    command void Timer.startPeriodic[uint8_t id](uint32_t dt) {
        start(id, dt, TRUE);
    }

    command void Timer.startOneShot[uint8_t id](uint32_t dt) {
        start(id, dt, FALSE);
    }

    command void Timer.stop[uint8_t id]() {
        if (id < N_TIMERS) {
            running[id] = FALSE;
            due[id] = FALSE;
        }
    }

    command bool Timer.isRunning[uint8_t id]() {
        return id < N_TIMERS && running[id];
    }

    /* A timer that falls behind by several periods fires once, then keeps its phase. */
    command void Clock.advance(uint32_t ms) {
        uint8_t id;
        bool any = FALSE;
        for (id = 0; id < N_TIMERS; id++) {
            if (!running[id]) {
                continue;
            }
            if (remaining[id] > ms) {
                remaining[id] -= ms;
                continue;
            }
            due[id] = TRUE;
            any = TRUE;
            if (periodic[id] && period[id] > 0) {
                remaining[id] = period[id] - (ms - remaining[id]) % period[id];
            } else {
                running[id] = FALSE;
            }
        }
        if (any) {
            post fireDue();
        }
    }

    command void Clock.untilDue(uint32_t *ms) {
        uint8_t id;
        *ms = DR_NESC_NEVER;
        for (id = 0; id < N_TIMERS; id++) {
            if (due[id]) {
                *ms = 0;
                return;
            }
            if (running[id] && remaining[id] < *ms) {
                *ms = remaining[id];
            }
        }
    }

    default event void Timer.fired[uint8_t id]() {
        (void)id;
    }
}
