; (5) Blocking time and call paths (InterruptRecord::blocking, path; latency_cause_kat_test.cpp).
; main idles (STI / JMP $). isr0 sends its EOI at once, then runs with IF = 0 through two nested
; routines: isr0 > routine_a > routine_b, routine_b counting CX = 1000 down with LOOP; it blocks
; up to its IRET. isr1 sends its EOI and enables interrupts at once (blocks only that long),
; then counts CX = 1000 down with IF = 1: another interrupt may nest there. isr2, isr3: (H).
[map all kat_blocking.map]
%include "latency_kat.inc"
        INIT 0xF0               ; IR0 .. IR3
idle:   sti
spin:   jmp spin                ; F000:0119: every interrupt returns here (no HLT: none is a start-up one)
        AT 0x200
isr0:   mov al, 0x20
        out 0xC0, al            ; EOI: the 8259A holds nothing for it from here, IF = 0 does
        push cx                 ; (isr1's count, when nested in it)
        call routine_a
        pop cx
        iret
        AT 0x240
isr1:   mov al, 0x20
        out 0xC0, al
        sti                     ; from here it blocks nothing
        mov cx, 1000
isr1_loop:
        loop isr1_loop
        iret
        ISRS 2, 7
        AT 0x800
routine_a:
        push bp
        call routine_b
        pop bp
        ret
routine_b:
        push bp                 ; the deepest write while blocking: the path ends here
        mov cx, 1000
rb_loop:
        loop rb_loop
        pop bp
        ret
        RESET
