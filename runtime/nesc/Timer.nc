/* Timer.nc - a timer of the given precision (TinyOS's interface, the part dynarole uses).
 * fired() is signalled from a task, never from an interrupt. */
interface Timer<precision_tag> {
    /* Fires every `dt` units from now on, until stopped. */
    command void startPeriodic(uint32_t dt);
    /* Fires once, `dt` units from now. */
    command void startOneShot(uint32_t dt);
    command void stop();
    command bool isRunning();
    event void fired();
}
