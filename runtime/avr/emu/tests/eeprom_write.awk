# eeprom_write.awk - reads `avr-objdump -d` of an ATmega128 image and fails unless the EEPROM's
# timed write is intact: at least one `sbi EECR, EEMWE`, each directly followed by
# `sbi EECR, EEWE` (EEWE must come within four cycles of EEMWE, or the chip writes nothing),
# and no `sbi EECR, EEWE` anywhere else. EECR is I/O address 0x1c, EEMWE bit 2, EEWE bit 1
# on the ATmega128. Usage: avr-objdump -d IMAGE.elf | awk -v image=IMAGE.elf -f eeprom_write.awk
function instruction(line) {
    sub(/^[^\t]*\t[^\t]*\t/, "", line) # the address and the bytes
    sub(/[ \t]*;.*$/, "", line)         # the disassembler's comment
    gsub(/[ \t]+/, " ", line)
    return line
}
/^ *[0-9a-f]+:\t/ {
    op = instruction($0)
    if (after_eemwe) {
        if (op == "sbi 0x1c, 1") {
            pairs++
        } else {
            printf "%s: EEWE not set right after EEMWE (next: %s)\n", image, op
            bad++
        }
        after_eemwe = 0
    } else if (op == "sbi 0x1c, 1") {
        printf "%s: EEWE set without EEMWE just before it: %s\n", image, $0
        bad++
    }
    if (op == "sbi 0x1c, 2") {
        after_eemwe = 1
    }
}
END {
    if (pairs == 0 && bad == 0) {
        printf "%s: no EEPROM write sequence (sbi EECR, EEMWE; sbi EECR, EEWE) found\n", image
        bad++
    }
    if (bad) {
        exit 1
    }
    printf "%s: %d EEPROM write sequence(s), EEWE right after EEMWE\n", image, pairs
}
