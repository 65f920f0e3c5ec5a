; The ROM of tests/scenarios/verdict/cases/bus_errors*.yaml (built by nasm at test time): one bus cycle of
; each kind nothing answers, then HLT with interrupts off. On the communication board
; (comm_cpu/comm_board.h) RAM is 00000-0FFFF, the DP-RAM D0000-D03FF, the ROM F0000-FFFFF; the
; 82510s decode I/O 0x80-0xAF, the 8259A 0xC0-0xC3.
        cpu     8086
        bits    16
        org     0                   ; ROM offset 0 = F000:0000 (physical F0000)

start:  cli
        mov     ax, 0xF000
        mov     ds, ax
        mov     byte [0x1234], 0x55 ; MEMW F1234: into the ROM, dropped      -> rom_write
        mov     al, 0x5A
        out     0x40, al            ; IOW 0040: no device decodes port 0x40  -> unmapped
        mov     ax, 0xE000
        mov     ds, ax
        mov     al, [0x0000]        ; MEMR E0000: no memory there, reads FF   -> unmapped
halt:   hlt
        jmp     halt

        times   0xFFF0 - ($ - $$) db 0xFF
        jmp     0xF000:start        ; the reset vector: FFFF:0000 = physical FFFF0
        times   0x10000 - ($ - $$) db 0xFF
