; (4) DP-RAM BUSY: DS = D000 (the DP-RAM window); IR3 wakes main from HLT; its handler returns to
; MOV AL,[0010h], a DP-RAM read the right port holds with BUSY. IR0 rises while the bus waits.
[map all kat_busy.map]
%include "latency_kat.inc"
        INIT 0xF6               ; IR0, IR3
        mov ax, 0xD000
        mov ds, ax
        nop
        sti
        hlt                     ; F000:011F: IR3 returns to F000:0120 (even)
read_here:
        mov al, [0x0010]        ; F000:0120
        times 40 nop
        hlt
        ISRS 0, 7
        RESET
