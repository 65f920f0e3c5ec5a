; rcsim — the training program of the core's profile-guided build (comm_cpu/tools/pgo/README.md).
; An instruction mix like the communication firmware's, written for this purpose and different
; from every program the benchmarks measure (comm_cpu/tools/protocol_loop.asm, the firmware ROM): port
; polling, byte and word memory operands in every addressing form, shifts and rotates, MUL/DIV,
; string instructions with and without REP, near/far calls and returns, INT n and a hardware
; interrupt handler (the driver raises INTR), accesses to a device window that answers through
; the bus handler with wait states, flag operations and conditional jumps both ways.
        cpu     8086
        bits    16
        org     0

STATUS  equ     0x40            ; bit 0 set every third read (train_main.cpp)
DATA    equ     0x42            ; a counter
EOI     equ     0x20
WINDOW  equ     0x8000          ; segment of the device window (handler, 1 wait state)
ROUNDS  equ     6000

start:  cli
        xor     ax, ax
        mov     ds, ax
        mov     word [0x20*4], isr
        mov     word [0x20*4+2], 0x1000
        mov     word [0x21*4], soft
        mov     word [0x21*4+2], 0x1000
        mov     ax, 0x2000
        mov     ds, ax
        mov     ax, 0x3000
        mov     es, ax
        mov     ax, 0x4000
        mov     ss, ax
        mov     sp, 0xfffe
        cld
        sti
        mov     bp, ROUNDS

round:  in      al, STATUS
        test    al, 1
        jz      round
        in      ax, DATA
        mov     bx, ax
        and     bx, 0x00ff
        mov     [bx+0x200], al          ; table store
        inc     byte [0x10]
        add     [bx+0x300], ax
        mov     cl, 3
        shl     bx, cl
        rol     ax, 1
        rcr     ax, 1
        sar     ax, 1
        shr     dx, 1
        xor     dx, dx
        mov     cx, 7
        div     cx
        mul     cx
        imul    cx
        mov     di, 0x400               ; strings
        mov     cx, 20
        mov     al, 0x55
        rep     stosb
        mov     si, 0x400
        mov     di, 0x600
        mov     cx, 10
        rep     movsw
        mov     si, 0x600
        mov     cx, 16
        xor     dx, dx
.sum:   lodsb
        add     dl, al
        adc     dh, 0
        loop    .sum
        mov     di, 0x400
        mov     cx, 20
        mov     al, 0x55
        repe    scasb
        push    es                      ; the device window
        mov     ax, WINDOW
        mov     es, ax
        mov     [es:0x10], dl
        mov     al, [es:0x11]
        mov     ax, [es:0x12]
        pop     es
        call    near_fn
        call    0x1000:far_fn
        int     0x21
        pushf
        popf
        cmp     dx, 0x1234
        je      .skip
        jl      .less
        xchg    ax, bx
        jmp     short .skip
.less:  neg     ax
        not     bx
.skip:  mov     si, bx
        and     si, 0x00fe
        lea     si, [si+4]
        mov     ax, [si+0x20]
        mov     [bp+si+0x40], ax        ; SS-relative
        cbw
        cwd
        mov     bx, 0x200
        xlatb
        out     DATA, al
        clc
        stc
        cmc
        dec     bp
        jnz     round
        hlt

near_fn:
        push    bx
        push    cx
        mov     bx, [0x10]
        and     bx, 0x00fe
        add     bx, [bx+0x100]
        sub     cx, bx
        test    cx, 0x8000
        jnz     .neg
        or      cx, 1
.neg:   pop     cx
        pop     bx
        ret

far_fn: push    ds
        push    ax
        mov     ax, ss
        mov     ds, ax
        mov     ax, [0xfff0]
        inc     ax
        mov     [0xfff0], ax
        pop     ax
        pop     ds
        retf

isr:    push    ax
        push    dx
        in      al, DATA
        mov     dl, al
        and     dl, 7
        cmp     dl, 3
        ja      .done
        inc     word [0x14]
.done:  mov     al, EOI
        out     EOI, al
        pop     dx
        pop     ax
        iret

soft:   inc     word [0x12]
        iret
