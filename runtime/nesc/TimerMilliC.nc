/* TimerMilliC.nc - one millisecond timer (TinyOS's generic component of the same name). */
generic configuration TimerMilliC() {
    provides interface Timer<TMilli>;
}
implementation {
    components TimerMilliP;

    Timer = TimerMilliP.Timer[unique("TimerMilliC.Timer")];
}
