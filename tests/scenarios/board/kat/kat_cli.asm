; (1) Interrupts disabled: DX = 0, BX = 1000h; IR3 wakes main from HLT; its handler (which leaves
; AX = 0020h) returns to CLI, 100 NOPs, STI, DIV BX (quotient 0), NOPs. IR3 rises again during
; the NOPs: it waits for STI and for the DIV, the instruction after it.
[map all kat_cli.map]
%include "latency_kat.inc"
        INIT 0xF7               ; IR3 only
        mov bx, 0x1000
        xor dx, dx
        nop
        sti
        hlt                     ; F000:011F: IR3's IRET returns to F000:0120 (even)
cli_here:
        cli                     ; F000:0120
        times 100 nop
sti_here:
        sti                     ; F000:0185
        div bx                  ; F000:0186
        times 40 nop
        hlt
        ISRS 0, 7
        RESET
