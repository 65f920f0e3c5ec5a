; (3) The instruction in progress: DX = 0, BX = 1000h; IR3 wakes main from HLT; its handler (which
; leaves AX = 0020h) returns to DIV BX: quotient 0, every trial subtraction fails, the fastest
; case. IR0 rises while DIV runs.
[map all kat_div.map]
%include "latency_kat.inc"
        INIT 0xF6               ; IR0, IR3
        mov ax, 5
        xor dx, dx
        mov bx, 0x1000
        sti
        hlt                     ; F000:0121: IR3 returns to F000:0122 (even)
div_here:
        div bx                  ; F000:0122
        times 40 nop
        hlt
        ISRS 0, 7
        RESET
