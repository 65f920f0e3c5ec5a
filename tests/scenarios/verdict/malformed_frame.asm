; The ROM of tests/scenarios/verdict/cases/malformed_frame.yaml (built by nasm at test time): a firmware that
; forwards a frame the main CPU must refuse. The shipped firmware never does (it NAKs every frame
; the main CPU's decoder would reject), so only a faulty ROM makes main_cpu_malformed_frames fail.
; It writes one whole chunk into data[0] of the DP-RAM (docs/system.md §4: D0000 + p*340, pflag[p]
; at +339, int2rbt at D03FF) and posts the "new chunk" word 0x10 (kind 1, port 0), as the
; firmware's to_dpram does, then halts with interrupts off.
;
; The frame is SOH "EC" STX "00" "00" ETX (docs/system.md §5.3): its checksum must be the 8-bit
; sum of "EC" STX "00" = 45+43+02+30+30 = 0xEA, so "00" is wrong: one malformed frame.
        cpu     8086
        bits    16
        org     0                   ; ROM offset 0 = F000:0000 (physical F0000)

DPRAM   equ     0xD000              ; segment of the DP-RAM
PFLAG0  equ     339
INT2RBT equ     0x3FF
EXT_USE equ     1

start:  cli
        mov     ax, 0xF000
        mov     ds, ax
        mov     ax, DPRAM
        mov     es, ax
        mov     si, frame
        xor     di, di
        mov     cx, frame_end - frame
        cld
        rep movsb                   ; data[0] = the frame
        mov     byte [es:PFLAG0], EXT_USE
        mov     byte [es:INT2RBT], 0x10 ; kind 1 (new chunk), port 0: raises INT_R
halt:   hlt
        jmp     halt

frame:  db      0x01, "EC", 0x02, "00", "00", 0x03
frame_end:

        times   0xFFF0 - ($ - $$) db 0xFF
        jmp     0xF000:start        ; the reset vector: FFFF:0000 = physical FFFF0
        times   0x10000 - ($ - $$) db 0xFF
