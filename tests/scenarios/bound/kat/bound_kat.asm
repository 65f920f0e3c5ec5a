; Known-answer ROM for the static bound (scenarios/bound, issue #47 item 6), built by nasm at test
; time with its map:  nasm -f bin -o bound_kat.bin bound_kat.asm  (writes bound_kat.map).
; tests/scenarios/bound/bound_kat_test.cpp bounds each handler below as the one source rs232_0
; (vector 0x20) and compares with the bound it computes by hand from the derivations here.
;
; The cost rules (scenarios/bound/README.md): a "line" is a maximal run of instructions each the
; only successor of the one before and its only predecessor, of one blocking kind, at most 16, no
; value-dependent form, no transfer but a direct JMP/CALL except a LAST conditional transfer
; (costed WorstClocks::branch(): .taken on the taken edge, .not_taken on the fall-through) or a
; LAST RET/IRET (sequence()). service = the longest path + 4 + the code wait state (the first
; fetch). Below, S(...) = sequence of those instructions, B(...) = branch, I(x) = instruction().
; Every handler is aligned on 16 bytes, so its instructions' offsets (and what timing takes of
; them, their parity) are fixed by the handler's own bytes.
;
; The board (docs/system.md §3): ROM F0000-FFFFF, RAM 00000-0FFFF, the 8259A at 0xC0/0xC2, port
; 0's 82510 at 0x80 + 2 x register. Start-up installs vector 0x20 (IR0 -> IR0_HANDLER, assemble
; with -DIR0_HANDLER=h_... to pick another) and enables interrupts; nothing else runs (HLT).
[map all bound_kat.map]
        cpu     8086
        bits    16
        org     0                   ; ROM offset 0 = F000:0000 (physical F0000)

%ifndef IR0_HANDLER
%define IR0_HANDLER h_straight
%endif

PIC_A0  equ     0xC0
PIC_A1  equ     0xC2
U0_RXD  equ     0x80                ; 82510 #0, RXD (bank 0)
U0_LSR  equ     0x8A                ; 82510 #0, register 5 (the FIFO/line status the loops read)

; `rcsim bound ROM` runs the ROM to read its vector table and takes the budget from the character
; time the start-up programs: the ports are set up as tests/scenarios/search/search_kat.asm does (from
; there).
; 82510 register offsets (x 2: the low byte lane, docs/system.md §3.2) and values, as the
; firmware's fw.h / hw.c uart_init
R_RXD   equ     0                   ; bank 0 (DLAB = 0) and bank 1
R_BAL   equ     0                   ; bank 0, DLAB = 1
R_BAH   equ     2                   ; bank 0, DLAB = 1
R_GER   equ     2                   ; bank 0, DLAB = 0
R_BANK  equ     4                   ; write, every bank
R_LCR   equ     6                   ; bank 0
R_IMD   equ     8                   ; bank 2
R_CLCF  equ     0                   ; bank 3
R_BACF  equ     2                   ; bank 3
R_RCM   equ     10                  ; bank 1
R_ICM   equ     14                  ; bank 1

; One 82510 at %1 for 9600,8E1 with the Rx FIFO interrupt (one character) on, bank 0 left
; selected: the firmware's uart_init sequence, without what this ROM does not use (BRGB timer,
; modem and Tx set-up, the Rx machine's error interrupt).
%macro  UART_INIT 1
        mov     al, 0x20            ; BANK <- 1 (WORK)
        out     %1 + R_BANK, al
        mov     al, 0x10            ; ICM: software reset (leaves bank 0 selected)
        out     %1 + R_ICM, al
        mov     al, 0x00            ; BANK <- 0 (NAS)
        out     %1 + R_BANK, al
        mov     al, 0x9B            ; LCR: DLAB | 8 bits, even parity, 1 stop (0x1B)
        out     %1 + R_LCR, al
        mov     al, 60              ; BRGA divisor 60: 18.432 MHz / (32 x 60) = 9600 bps
        out     %1 + R_BAL, al
        mov     al, 0
        out     %1 + R_BAH, al
        mov     al, 0x1B            ; LCR: 8E1, DLAB = 0
        out     %1 + R_LCR, al
        mov     al, 0x40            ; BANK <- 2 (GEN)
        out     %1 + R_BANK, al
        mov     al, 0x00            ; IMD: 4-byte Rx FIFO, automatic INT (FMD stays 0: threshold 1)
        out     %1 + R_IMD, al
        mov     al, 0x60            ; BANK <- 3 (MODM)
        out     %1 + R_BANK, al
        mov     al, 0x50            ; CLCF: Rx and Tx clocks from BRGA, 16x
        out     %1 + R_CLCF, al
        mov     al, 0x04            ; BACF: BRGA is a baud-rate generator
        out     %1 + R_BACF, al
        mov     al, 0x20            ; BANK <- 1 (WORK)
        out     %1 + R_BANK, al
        mov     al, 0xB0            ; RCM: receiver enable, flush the Rx FIFO and machine
        out     %1 + R_RCM, al
        mov     al, 0x04            ; ICM: status clear
        out     %1 + R_ICM, al
        mov     al, 0x00            ; BANK <- 0 (NAS): GER and RXD
        out     %1 + R_BANK, al
        mov     al, 0x01            ; GER: Rx FIFO interrupt only
        out     %1 + R_GER, al
%endmacro

start:  cli
        xor     ax, ax
        mov     ss, ax
        mov     sp, 0x0800
        mov     ds, ax
        mov     word [0x20 * 4], IR0_HANDLER
        mov     word [0x20 * 4 + 2], 0xF000
        UART_INIT 0x80              ; the three 82510s (0x80, 0x90, 0xA0): the budget is the
        UART_INIT 0x90              ; character time of the fastest port the start-up sets
        UART_INIT 0xA0
        mov     al, 0x13            ; ICW1: edge, single, ICW4
        out     PIC_A0, al
        mov     al, 0x20            ; ICW2: IR n -> vector 20h + n
        out     PIC_A1, al
        mov     al, 0x01            ; ICW4: 8086 mode, normal EOI
        out     PIC_A1, al
        mov     al, 0xFE            ; OCW1: IR0 only
        out     PIC_A1, al
        sti
        jmp     idle
idle:   hlt
        jmp     idle

; (a) A straight line: one line of 7 instructions ending in IRET.
;     service = S(push ax .. iret) + 5
        align   16
h_straight:
        push    ax                  ; 50
        mov     ax, 0x1234          ; B8 34 12
        add     ax, 5               ; 83 C0 05 (imm8, sign-extended)
        mov     al, 0x20            ; B0 20      non-specific EOI
        out     PIC_A0, al          ; E6 C0
        pop     ax                  ; 58
        iret                        ; CF

; (b) A counted loop: MOV CX,N; LOOP. CX = N >= 1 at entry: the header (add) runs N times, the
;     LOOP is taken N - 1 times and falls through once. The header has two predecessors (MOV CX
;     and the LOOP), so MOV CX is a line of its own.
;     service(N) = I(mov cx) + (N - 1) B(add, loop).taken + B(add, loop).not_taken
;                  + S(mov al, out, iret) + 5
;     service(20) - service(10) = 10 x B(add, loop).taken (the two handlers differ only in N).
        align   16
h_loop10:
        mov     cx, 10              ; B9 0A 00
.l:     add     ax, 3               ; 83 C0 03
        loop    .l                  ; E2 FB
        mov     al, 0x20            ; B0 20
        out     PIC_A0, al          ; E6 C0
        iret                        ; CF

        align   16
h_loop20:
        mov     cx, 20              ; B9 14 00
.l:     add     ax, 3               ; 83 C0 03
        loop    .l                  ; E2 FB
        mov     al, 0x20            ; B0 20
        out     PIC_A0, al          ; E6 C0
        iret                        ; CF

; (c) Nested calls: the handler calls f1, f1 calls f2; calls are inlined per call site, so each
;     return point has one predecessor (the RET) but a RET ends a line:
;     service = S(push ax, call f1, inc ax, call f2, mov ax 7, ret) + S(add ax ax, ret)
;               + S(mov al, out, pop ax, iret) + 5
        align   16
h_calls:
        push    ax                  ; 50
        call    f1                  ; E8 rel16
        mov     al, 0x20            ; B0 20
        out     PIC_A0, al          ; E6 C0
        pop     ax                  ; 58
        iret                        ; CF
f1:     inc     ax                  ; 40
        call    f2                  ; E8 rel16
        add     ax, ax              ; 01 C0
        ret                         ; C3
f2:     mov     ax, 7               ; B8 07 00
        ret                         ; C3

; (d) A jump table: BX <= 3 after CMP/JA, doubled by SHL, JMP CS:[BX+table] reads 4 targets from
;     the ROM. The indirect JMP is costed alone (I), SHL alone (its only successor cannot join a
;     line). t1 does the most work: the longest path is the fall-through to t1.
;     via t_k: B(push ax, push bx, cmp, ja).not_taken + I(shl) + I(jmp) + S(t_k .. jmp done)
;     out of range: B(push ax, push bx, cmp, ja).taken; both then + S(done: mov al .. iret) + 5
        align   16
h_table:
        push    ax                  ; 50
        push    bx                  ; 53
        cmp     bx, 3               ; 83 FB 03
        ja      .done               ; 77 rel8
        shl     bx, 1               ; D1 E3
        jmp     [cs:bx + .table]    ; 2E FF A7 disp16
.t0:    inc     ax                  ; 40
        jmp     .done               ; EB rel8
.t1:    add     ax, 0x1000          ; 05 00 10
        add     ax, bx              ; 01 D8
        add     ax, bx              ; 01 D8
        add     ax, bx              ; 01 D8
        add     ax, bx              ; 01 D8
        jmp     .done               ; EB rel8
.t2:    dec     ax                  ; 48
        dec     ax                  ; 48
        jmp     .done               ; EB rel8
.t3:    jmp     .done               ; EB rel8
.done:  mov     al, 0x20            ; B0 20
        out     PIC_A0, al          ; E6 C0
        pop     bx                  ; 5B
        pop     ax                  ; 58
        iret                        ; CF
.table: dw      .t0, .t1, .t2, .t3

; (e) A FIFO-level loop: CX = the FIFO level (AL & 7, CH = 0) is 0..7; JCXZ leaves at 0, so the
;     loop is entered with CX in 1..7: the header (in) runs at most 7 times.
;     service = B(push ax .. jcxz).not_taken + 6 B(in, loop).taken + B(in, loop).not_taken
;               + S(done: mov al .. iret) + 5       (JCXZ taken: B(..).taken + S(done) is less)
        align   16
h_fifo:
        push    ax                  ; 50
        push    cx                  ; 51
        push    dx                  ; 52
        mov     dx, U0_LSR          ; BA 8A 00
        in      al, dx              ; EC
        and     al, 7               ; 24 07
        mov     cl, al              ; 88 C1
        xor     ch, ch              ; 30 ED
        jcxz    .done               ; E3 rel8
.l:     in      al, U0_RXD          ; E4 80
        loop    .l                  ; E2 FC
.done:  mov     al, 0x20            ; B0 20
        out     PIC_A0, al          ; E6 C0
        pop     dx                  ; 5A
        pop     cx                  ; 59
        pop     ax                  ; 58
        iret                        ; CF

; (f) An unbounded loop: polling a status bit, no count the code states. The analysis names the
;     header h_poll+0x5 (no label of its own, on purpose) and the line to add; with
;     `h_poll+0x5 iterations 5  # ...` (bound_kat.annotations) the header runs 5 times:
;     service = S(push ax, push dx, mov dx) + 4 B(in, test, jz).taken + B(in, test, jz).not_taken
;               + S(mov al, out, pop dx, pop ax, iret) + 5
        align   16
h_poll:
        push    ax                  ; 50
        push    dx                  ; 52
        mov     dx, U0_LSR          ; BA 8A 00
        in      al, dx              ; EC          h_poll+0x5
        test    al, 1               ; A8 01
        jz      h_poll + 5          ; 74 rel8
        mov     al, 0x20            ; B0 20
        out     PIC_A0, al          ; E6 C0
        pop     dx                  ; 5A
        pop     ax                  ; 58
        iret                        ; CF

; (g) A handler that re-enables interrupts: EOI, STI, work, CLI, IRET. Three lines of two
;     blocking kinds: IF = 0 up to the STI, IF = 1 after it (and the EOI written) up to the CLI,
;     IF = 0 again after it.
;     service  = S(push ax, mov al, out, sti) + S(mov ax, add, add, add, cli) + S(pop ax, iret) + 5
;     blocking = S(push ax, mov al, out, sti) + S(pop ax, iret) + 5
        align   16
h_nested:
        push    ax                  ; 50
        mov     al, 0x20            ; B0 20
        out     PIC_A0, al          ; E6 C0      EOI first
        sti                         ; FB
        mov     ax, 1               ; B8 01 00
        add     ax, ax              ; 01 C0
        add     ax, ax              ; 01 C0
        add     ax, ax              ; 01 C0
        cli                         ; FA
        pop     ax                  ; 58
        iret                        ; CF

        times   0xFFF0 - ($ - $$) db 0xFF
        jmp     0xF000:start        ; the reset vector: FFFF:0000 = physical FFFF0
        times   0x10000 - ($ - $$) db 0xFF
