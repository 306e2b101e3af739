/* Boot.nc - signalled once the platform has started (TinyOS's interface of the same name). */
interface Boot {
    event void booted();
}
