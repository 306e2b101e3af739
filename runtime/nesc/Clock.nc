/* Clock.nc - time passing, as the platform's timer interrupt reports it to the timers. */
interface Clock {
    command void advance(uint32_t ms);
    /* *ms: milliseconds until the first running timer is due (0: one is due and not
     * signalled yet), DR_NESC_NEVER when none runs: how long a platform may sleep. (An out
     * parameter: nesC 1.4.0 returns a uint32_t through an interface as an int on the AVR.) */
    command void untilDue(uint32_t *ms);
}
