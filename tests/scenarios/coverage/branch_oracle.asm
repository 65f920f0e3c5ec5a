; Every conditional jump of the 8086 under every combination of the flags they test, for the
; branch oracle (branch_oracle_test.cpp): Jcc 70-7F, LOOPNZ, LOOPZ, LOOP, JCXZ, each jumping over
; one NOP, so that "taken" (the next instruction is the target, 3 bytes on) and "not taken" (2
; bytes on) can be told from the instruction boundaries alone. Loaded at 1000:0000 of the core's
; test board (tests/comm_cpu/i8086/cpu_board.h), no interrupts; ends in HLT.
        cpu     8086
        bits    16
        org     0

N       equ     64                      ; CF PF ZF SF OF AF: every combination

        push    cs
        pop     ds
        xor     si, si
top:    mov     ax, [flags + si]
        push    ax
        popf                            ; TF and IF stay 0
%assign op 0x70
%rep 16
        db      op, 1                   ; Jcc over the NOP
        nop
%assign op op + 1
%endrep
%assign op 0xE0
%rep 4
        mov     cx, [counts + si]       ; CX 0, 1, 2, 3 in turn (MOV leaves the flags)
        db      op, 1                   ; LOOPNZ, LOOPZ, LOOP, JCXZ over the NOP
        nop
%assign op op + 1
%endrep
        add     si, 2
        cmp     si, N * 2
        jb      top
        hlt

flags:
%assign i 0
%rep N
        dw      (i & 1) * 0x0001 + ((i >> 1) & 1) * 0x0004 + ((i >> 2) & 1) * 0x0040 + ((i >> 3) & 1) * 0x0080 + ((i >> 4) & 1) * 0x0800 + ((i >> 5) & 1) * 0x0010
%assign i i + 1
%endrep
counts:
%assign i 0
%rep N
        dw      i & 3
%assign i i + 1
%endrep
