# dr_warn.mk - the C language and warning flags of every dynarole build, in one place: every
# runtime Makefile (lattice, paper, token, fuzz, avr, nesc) includes this file; the code
# generator writes DR_WARN into each compiled program's Makefile and the simulator compiles
# the generated C with it (both read this file through crates/dynarole-codegen, which takes
# the words of the one line `DR_WARN = ...`: keep it on one line, flags only).
#
# C99 with no extensions (-pedantic), every warning an error, and the ones that catch what
# an 8-bit target makes costly: silent narrowing (-Wconversion), shadowed names, functions
# without prototypes.
DR_WARN = -std=c99 -Wall -Wextra -Werror -pedantic -Wshadow -Wconversion -Wstrict-prototypes -Wmissing-prototypes
# What nesC's own output can meet (runtime/nesc compiles the component with it, the runtime's
# C files with DR_WARN): its headers are not -pedantic and have functions without prototypes.
DR_WARN_NESC = $(filter-out -pedantic -Wmissing-prototypes,$(DR_WARN))
