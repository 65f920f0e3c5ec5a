; Functions of known clock counts for the profiler's known-answer test
; (tests/scenarios/trace/profiler_kat_test.cpp, where the counts are derived from the 8086 timing tables).
; Assembled with `nasm -f bin`, loaded at 1000:0000 into RAM without wait states. The test raises
; INTR with vector 20h (IR0) before the first instruction, and IR1 (vector 21h) when IR0's handler
; writes port 80h.
        bits 16
        org 0
        [map all profile_kat.map]

; A call in the same state of the bus interface every time: the 6-byte queue full after five
; NOPs (3 clocks each against 4 clocks per 2-byte fetch), the CALL at an odd address, so the
; return address is even like every function's entry (align 2).
%macro CALLQ 1
        align 2, nop
        times 5 nop
        call %1
%endmacro

start:  sti                     ; INTR is taken after the next instruction (STI's one-instruction delay):
        call outer              ; right after this CALL, before outer's first instruction
        mov cx, 10
        CALLQ fill              ; 10 bytes
        mov cx, 30
        CALLQ fill              ; 30 bytes
        CALLQ leaf_b
        hlt

outer:  CALLQ leaf_a
        CALLQ leaf_a
        ret

        align 2, nop
leaf_a: times 20 nop            ; 20 x 3 clocks
        ret

        align 2, nop
leaf_b: times 50 nop            ; 50 x 3 clocks
        ret

        align 2, nop
fill:   rep stosb               ; ES:DI, CX bytes: 9 + 10 clocks per byte
        ret

isr0:   out 0x80, al            ; the IR0 handler (vector 20h): the test raises IR1 now
        sti                     ; ... which is taken after the next instruction
        CALLQ leaf_a
        iret

isr1:   CALLQ leaf_b            ; the IR1 handler (vector 21h), nested in isr0
        iret
