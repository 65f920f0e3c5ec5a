; The ROM of tests/scenarios/cli/symbols_alone.sh (built by nasm at test time, with its map): a
; user's firmware whose one interrupt waits in a routine of its own with IF = 0, so that the
; latency cause of rs232_0 names that routine when --symbols gives the map, and only addresses
; without it.
;
; On the communication board (docs/system.md §3) RAM is 00000-0FFFF, the ROM F0000-FFFFF; the
; 8259A is at 0xC0/0xC2, port 0's 82510 at 0x80 + 2 x register, on IR0. After its reset the
; 82510's Tx FIFO is empty (GSR bit 1): enabling that source in GER (bank 0, register 1) raises
; its INT at once.
[map all symbols_rom.map]
        cpu     8086
        bits    16
        org     0                   ; ROM offset 0 = F000:0000 (physical F0000)

PIC_A0  equ     0xC0
PIC_A1  equ     0xC2
U0_GER  equ     0x82
GER_TXF equ     0x02

start:  cli
        xor     ax, ax
        mov     ss, ax
        mov     sp, 0x0800
        mov     ds, ax
        mov     word [0x20 * 4], isr_port0  ; vector 20h (IR0): F000:isr_port0
        mov     word [0x20 * 4 + 2], 0xF000
        mov     al, 0x13            ; ICW1: edge, single, ICW4
        out     PIC_A0, al
        mov     al, 0x20            ; ICW2: IR n -> vector 20h + n
        out     PIC_A1, al
        mov     al, 0x01            ; ICW4: 8086 mode, normal EOI
        out     PIC_A1, al
        mov     al, 0xFE            ; OCW1: IR0 only
        out     PIC_A1, al
        sti
        call    hold_if
idle:   hlt
        jmp     idle

; Raises port 0's interrupt with IF = 0 and keeps it waiting for 300 NOPs (900 clocks).
hold_if:
        cli
        mov     al, GER_TXF
        out     U0_GER, al
        times   300 nop
        sti
        ret

isr_port0:
        push    ax
        xor     al, al
        out     U0_GER, al          ; the source off: INT falls
        mov     al, 0x20            ; non-specific EOI
        out     PIC_A0, al
        pop     ax
        iret

        times   0xFFF0 - ($ - $$) db 0xFF
        jmp     0xF000:start        ; the reset vector: FFFF:0000 = physical FFFF0
        times   0x10000 - ($ - $$) db 0xFF
