; The ROM of the coverage known-answer test (coverage_run_test.cpp, CoverageKat): a program of
; known control flow for the communication board (ROM F0000-FFFFF, reset at FFFF0), read with
; the symbols of coverage_kat.sym (sizes given, so every address range is known). Interrupts stay
; off; the program ends in HLT.
;
; Executions of each instruction, by hand (offset: instruction, count):
;   main  (F0000, 32 bytes; two 16-byte lines: F0000-F000F line 1, F0010-F001F line 2)
;     00 cli 1 | 01 mov cx,3 1 | 04 dec cx 3 | 05 jnz 3 (taken 2, not taken 1)
;     07 call count 1 | 0A call count 1 | 0D mov ax,5 1            -> line 1: 11 instructions
;     10 cmp ax,5 1 | 13 je 1 (taken 1, not taken 0) | 15 nop 0 | 16 hlt 1 | 17 jmp 0
;                                                                   -> line 2: 3 instructions
;   count (F0020, 16 bytes, line 3), called twice:
;     20 mov cx,4 2 | 23 loop 8 (CX 4,3,2,1 each call: taken 6, not taken 2)
;     25 jcxz 2 (CX = 0: taken 2, not taken 0) | 27 nop 0 | 28 ret 2  -> line 3: 14 instructions
;   unused (F0030, 16 bytes, line 4): never called                 -> line 4: 0
; Functions: main entered 1, count 2, unused 0.
        cpu     8086
        bits    16
        org     0

main:   cli
        mov     cx, 3
.l1:    dec     cx
        jnz     .l1
        call    count
        call    count
        mov     ax, 5
        cmp     ax, 5                   ; 3 bytes (83 F8 05)
        je      .eq
        nop
.eq:    hlt
        jmp     .eq
        times   0x20 - ($ - $$) nop     ; an error if main outgrew its 32 bytes

count:  mov     cx, 4
.l2:    loop    .l2
        jcxz    .z
        nop
.z:     ret
        times   0x30 - ($ - $$) nop

unused: test    al, 1
        jz      .u
.u:     ret
        times   0x40 - ($ - $$) nop

        times   0xFFF0 - ($ - $$) db 0xFF
        jmp     0xF000:main             ; the reset vector: FFFF:0000 = physical FFFF0
        times   0x10000 - ($ - $$) db 0xFF
