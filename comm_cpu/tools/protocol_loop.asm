; rcsim — the protocol-like loop of `rcsim bench cpu` (docs/performance.md, "8086 core"): the
; same image runs on the rcsim 8086 core and on libx86emu, side by side, from 1000:0000 to HLT.
; Each frame polls a UART-like status port until a character is ready, stores the character in
; a 64-byte receive ring, copies the ring with REP MOVSW, checksums the copy in a loop, sends
; the checksum to a port and goes on with the next frame: the work of the communication
; firmware's receive path, without interrupts (libx86emu has no 8259A to deliver them).
;
; The bench's ports: STATUS reads 01h every 4th time (00h otherwise), DATA returns a counter,
; RESULT is written once per frame. 128 instructions per frame (REP MOVSW counts once):
; poll 4 x 3, IN, CALL, put_byte 6, 3 MOVs, REP MOVSW, CALL, checksum 3 + 32 x 3 + 1, OUT,
; DEC, JNZ; 54 688 frames make 7.0 M instructions.
        cpu     8086
        bits    16
        org     0

STATUS  equ     0x80
DATA    equ     0x82
RESULT  equ     0x84
FRAMES  equ     54688
BLOCK   equ     32              ; words: the whole 64-byte ring
head    equ     0x0000          ; DS:0000 ring index
ring    equ     0x0100          ; DS:0100 receive ring, ES:0100 its copy

start:  mov     ax, 0x2000
        mov     ds, ax
        mov     ax, 0x3000
        mov     es, ax
        mov     ax, 0x4000
        mov     ss, ax
        mov     sp, 0xfffe
        cld
        mov     bp, FRAMES
frame:  in      al, STATUS
        test    al, 1
        jz      frame
        in      al, DATA
        call    put_byte
        mov     si, ring
        mov     di, ring
        mov     cx, BLOCK
        rep     movsw
        call    checksum
        out     RESULT, al
        dec     bp
        jnz     frame
        hlt

put_byte:                       ; ring[head] = AL; head = (head + 1) mod 64
        mov     bx, [head]
        mov     [bx+ring], al
        inc     bx
        and     bx, 63
        mov     [head], bx
        ret

checksum:                       ; AX = sum of the BLOCK words at ES:ring
        xor     ax, ax
        mov     bx, ring
        mov     cx, BLOCK
.next:  add     ax, [es:bx]
        add     bx, 2
        loop    .next
        ret
