/* Clock.nc - time passing, as the platform's timer interrupt reports it to the timers. */
interface Clock {
    command void advance(uint32_t ms);
}
