; (6) Main-program code holds IF = 0: main enables interrupts, then calls hold_irqs, which clears
; IF, counts CX = 100 down with LOOP and sets IF again before it returns. IR3 rises inside.
[map all kat_main_hold.map]
%include "latency_kat.inc"
        INIT 0xF7               ; IR3 only
        sti
        nop                     ; interrupts could be taken from here: start-up is over
        call hold_irqs
spin:   jmp spin
        ISRS 0, 7
        AT 0x800
hold_irqs:
        cli                     ; F000:0800
        mov cx, 100
hold_loop:
        loop hold_loop
sti_here:
        sti
        ret                     ; the instruction after STI: IR3 is taken at its end
        RESET
