! rcsim communication firmware -- start-up, interrupt entry/exit, port and DP-RAM access.
! as86 -0 syntax.  Linked first by ld86 -0 -d -i -T 0 -D 0, so `start' is at ROM offset 0
! (physical F0000, CS = F000); the reset stub at FFFF:0000 (ROM offset FFF0) is written by mkrom:
!     FFFF0: EA <start> 00 F0        jmp far F000:start
!
! Data segment: DS = SS = ES = DATA_SEG (physical 00400).  ld86 places the initialised-data
! image right after the code, at paragraph __segoff of the image; __edata is its size and
! __end the end of BSS (both DS offsets, data linked at 0).
!
! bcc calling convention: arguments pushed right to left as words, caller pops; result in AX;
! a C function preserves BP, SI, DI (and DS, SS); AX, BX, CX, DX, ES and flags are scratch.
! bcc's code never uses ES (no string instructions), so dp_rd/dp_wr leave ES = DP_SEG.
! DS = SS = DATA_SEG from the `call _main' on; nothing changes DS again (isr.s relies on it).

DATA_SEG  = 0x0040
STACK_TOP = 0x0C00
DP_SEG    = 0xD000

.globl start
.globl __segoff
.globl __edata
.globl __end
.globl _main
.globl _unexpected
.globl _ticks
.globl _isr_port0
.globl _isr_port1
.globl _isr_port2
.globl _isr_dpram
.globl _isr_unexpected
.globl _inb
.globl _outb
.globl _dp_rd
.globl _dp_wr
.globl _irq_off
.globl _mul_div_up
.globl _irq_restore
.globl _irq_on

.text
start:
	cli
	cld
! copy the initialised data from ROM (CS + __segoff : 0) to DATA_SEG:0
	mov	ax,cs
	add	ax,#__segoff
	mov	ds,ax
	mov	ax,#DATA_SEG
	mov	es,ax
	xor	si,si
	xor	di,di
	mov	cx,#__edata
	rep
	movsb
! clear BSS (DI = __edata)
	mov	cx,#__end
	sub	cx,#__edata
	xor	al,al
	rep
	stosb
! vector table: every vector -> _isr_unexpected, then 0x20..0x23
	xor	ax,ax
	mov	es,ax
	xor	di,di
	mov	cx,#256
	mov	dx,cs
vec_fill:
	mov	ax,#_isr_unexpected
	stosw
	mov	ax,dx
	stosw
	loop	vec_fill
	seg	es
	mov	word ptr [0x80],#_isr_port0
	seg	es
	mov	word ptr [0x84],#_isr_port1
	seg	es
	mov	word ptr [0x88],#_isr_port2
	seg	es
	mov	word ptr [0x8C],#_isr_dpram
! DS = SS = ES = DATA_SEG, stack below the port buffers
	mov	ax,#DATA_SEG
	mov	ds,ax
	mov	es,ax
	mov	ss,ax
	mov	sp,#STACK_TOP
	call	_main
halt_forever:
	cli
	hlt
	jmp	halt_forever

! ---- interrupt entries ---------------------------------------------------------------------
! IR0..IR3 (_isr_port0..2, _isr_dpram) are in isr.s.
! Any other vector (CPU exceptions, the 8259A's spurious IR7 = vector 0x27): count and return.
! No EOI: a spurious IR7 sets no in-service bit.
_isr_unexpected:
	push	ds
	push	ax
	mov	ax,#DATA_SEG
	mov	ds,ax
	inc	word ptr [_unexpected]
	pop	ax
	pop	ds
	iret

! ---- port I/O ------------------------------------------------------------------------------
! unsigned char inb(unsigned port)
_inb:
	mov	bx,sp
	mov	dx,2[bx]
	in	al,dx
	xor	ah,ah
	ret

! void outb(unsigned port, unsigned char value)
_outb:
	mov	bx,sp
	mov	dx,2[bx]
	mov	al,4[bx]
	out	dx,al
	ret

! ---- DP-RAM (left port, D000:0000..03FF) -----------------------------------------------------
! unsigned char dp_rd(unsigned offset)
_dp_rd:
	mov	bx,sp
	mov	bx,2[bx]
	mov	ax,#DP_SEG
	mov	es,ax
	seg	es
	mov	al,[bx]
	xor	ah,ah
	ret

! void dp_wr(unsigned offset, unsigned char value)
_dp_wr:
	mov	bx,sp
	mov	al,4[bx]
	mov	bx,2[bx]
	mov	dx,#DP_SEG
	mov	es,dx
	seg	es
	mov	[bx],al
	ret

! ---- arithmetic ----------------------------------------------------------------------------
! unsigned mul_div_up(unsigned a, unsigned b, unsigned c): ceil(a * b / c) with the 8086's
! 32-bit MUL and DIV (bcc's long arithmetic needs its library, which is not linked).  0xFFFF
! when the quotient does not fit in 16 bits or c = 0, so DIV never traps.  a * b + c - 1 stays
! below 2^32 (at most 0xFFFE0001 + 0xFFFE).
_mul_div_up:
	mov	bx,sp
	mov	ax,2[bx]
	mov	cx,4[bx]
	mul	cx
	mov	cx,6[bx]
	jcxz	mdu_big
	add	ax,cx
	adc	dx,#0
	sub	ax,#1
	sbb	dx,#0
	cmp	dx,cx
	jae	mdu_big
	div	cx
	ret
mdu_big:
	mov	ax,#0xFFFF
	ret

! ---- interrupt flag ------------------------------------------------------------------------
! unsigned irq_off(void): CLI, returns the previous FLAGS
_irq_off:
	pushf
	pop	ax
	cli
	ret

! void irq_restore(unsigned flags)
_irq_restore:
	mov	bx,sp
	push	word ptr 2[bx]
	popf
	ret

! void irq_on(void)
_irq_on:
	sti
	ret
