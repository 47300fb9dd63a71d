define dso_local void @trax_main() {
entry:
  %i = alloca i32, align 4
  %msg.args = alloca [4 x i32], align 4
  br label %start

start:                                            ; preds = %entry
  %0 = call i32 @"trax::global_id"()
  %1 = urem i32 %0, 3
  store i32 %1, i32* %i, align 4
  %2 = load i32, i32* %i, align 4
  %inbounds = icmp ult i32 %2, 3
  br i1 %inbounds, label %check.ok, label %check.fail

check.fail:                                       ; preds = %start
  %3 = getelementptr inbounds [4 x i32], [4 x i32]* %msg.args, i32 0, i32 0
  store i32 ptrtoint ([56 x i8]* @.str.0 to i32), i32* %3, align 4
  %4 = getelementptr inbounds [4 x i32], [4 x i32]* %msg.args, i32 0, i32 1
  store i32 56, i32* %4, align 4
  %5 = getelementptr inbounds [4 x i32], [4 x i32]* %msg.args, i32 0, i32 2
  store i32 %2, i32* %5, align 4
  %6 = bitcast [4 x i32]* %msg.args to i32*
  %7 = ptrtoint i32* %6 to i32
  call void asm sideeffect ".set push\0A.set noat\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $0,$$\\r\0A.set .Ltrax_rs_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $0,$$zero\0A.set .Ltrax_rs_${:uid}, 0\0A.endif\0A.ifc $0,$$at\0A.set .Ltrax_rs_${:uid}, 1\0A.endif\0A.ifc $0,$$v0\0A.set .Ltrax_rs_${:uid}, 2\0A.endif\0A.ifc $0,$$v1\0A.set .Ltrax_rs_${:uid}, 3\0A.endif\0A.ifc $0,$$a0\0A.set .Ltrax_rs_${:uid}, 4\0A.endif\0A.ifc $0,$$a1\0A.set .Ltrax_rs_${:uid}, 5\0A.endif\0A.ifc $0,$$a2\0A.set .Ltrax_rs_${:uid}, 6\0A.endif\0A.ifc $0,$$a3\0A.set .Ltrax_rs_${:uid}, 7\0A.endif\0A.ifc $0,$$t0\0A.set .Ltrax_rs_${:uid}, 8\0A.endif\0A.ifc $0,$$t1\0A.set .Ltrax_rs_${:uid}, 9\0A.endif\0A.ifc $0,$$t2\0A.set .Ltrax_rs_${:uid}, 10\0A.endif\0A.ifc $0,$$t3\0A.set .Ltrax_rs_${:uid}, 11\0A.endif\0A.ifc $0,$$t4\0A.set .Ltrax_rs_${:uid}, 12\0A.endif\0A.ifc $0,$$t5\0A.set .Ltrax_rs_${:uid}, 13\0A.endif\0A.ifc $0,$$t6\0A.set .Ltrax_rs_${:uid}, 14\0A.endif\0A.ifc $0,$$t7\0A.set .Ltrax_rs_${:uid}, 15\0A.endif\0A.ifc $0,$$s0\0A.set .Ltrax_rs_${:uid}, 16\0A.endif\0A.ifc $0,$$s1\0A.set .Ltrax_rs_${:uid}, 17\0A.endif\0A.ifc $0,$$s2\0A.set .Ltrax_rs_${:uid}, 18\0A.endif\0A.ifc $0,$$s3\0A.set .Ltrax_rs_${:uid}, 19\0A.endif\0A.ifc $0,$$s4\0A.set .Ltrax_rs_${:uid}, 20\0A.endif\0A.ifc $0,$$s5\0A.set .Ltrax_rs_${:uid}, 21\0A.endif\0A.ifc $0,$$s6\0A.set .Ltrax_rs_${:uid}, 22\0A.endif\0A.ifc $0,$$s7\0A.set .Ltrax_rs_${:uid}, 23\0A.endif\0A.ifc $0,$$t8\0A.set .Ltrax_rs_${:uid}, 24\0A.endif\0A.ifc $0,$$t9\0A.set .Ltrax_rs_${:uid}, 25\0A.endif\0A.ifc $0,$$k0\0A.set .Ltrax_rs_${:uid}, 26\0A.endif\0A.ifc $0,$$k1\0A.set .Ltrax_rs_${:uid}, 27\0A.endif\0A.ifc $0,$$gp\0A.set .Ltrax_rs_${:uid}, 28\0A.endif\0A.ifc $0,$$sp\0A.set .Ltrax_rs_${:uid}, 29\0A.endif\0A.ifc $0,$$fp\0A.set .Ltrax_rs_${:uid}, 30\0A.endif\0A.ifc $0,$$ra\0A.set .Ltrax_rs_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $1,$$\\r\0A.set .Ltrax_rt_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $1,$$zero\0A.set .Ltrax_rt_${:uid}, 0\0A.endif\0A.ifc $1,$$at\0A.set .Ltrax_rt_${:uid}, 1\0A.endif\0A.ifc $1,$$v0\0A.set .Ltrax_rt_${:uid}, 2\0A.endif\0A.ifc $1,$$v1\0A.set .Ltrax_rt_${:uid}, 3\0A.endif\0A.ifc $1,$$a0\0A.set .Ltrax_rt_${:uid}, 4\0A.endif\0A.ifc $1,$$a1\0A.set .Ltrax_rt_${:uid}, 5\0A.endif\0A.ifc $1,$$a2\0A.set .Ltrax_rt_${:uid}, 6\0A.endif\0A.ifc $1,$$a3\0A.set .Ltrax_rt_${:uid}, 7\0A.endif\0A.ifc $1,$$t0\0A.set .Ltrax_rt_${:uid}, 8\0A.endif\0A.ifc $1,$$t1\0A.set .Ltrax_rt_${:uid}, 9\0A.endif\0A.ifc $1,$$t2\0A.set .Ltrax_rt_${:uid}, 10\0A.endif\0A.ifc $1,$$t3\0A.set .Ltrax_rt_${:uid}, 11\0A.endif\0A.ifc $1,$$t4\0A.set .Ltrax_rt_${:uid}, 12\0A.endif\0A.ifc $1,$$t5\0A.set .Ltrax_rt_${:uid}, 13\0A.endif\0A.ifc $1,$$t6\0A.set .Ltrax_rt_${:uid}, 14\0A.endif\0A.ifc $1,$$t7\0A.set .Ltrax_rt_${:uid}, 15\0A.endif\0A.ifc $1,$$s0\0A.set .Ltrax_rt_${:uid}, 16\0A.endif\0A.ifc $1,$$s1\0A.set .Ltrax_rt_${:uid}, 17\0A.endif\0A.ifc $1,$$s2\0A.set .Ltrax_rt_${:uid}, 18\0A.endif\0A.ifc $1,$$s3\0A.set .Ltrax_rt_${:uid}, 19\0A.endif\0A.ifc $1,$$s4\0A.set .Ltrax_rt_${:uid}, 20\0A.endif\0A.ifc $1,$$s5\0A.set .Ltrax_rt_${:uid}, 21\0A.endif\0A.ifc $1,$$s6\0A.set .Ltrax_rt_${:uid}, 22\0A.endif\0A.ifc $1,$$s7\0A.set .Ltrax_rt_${:uid}, 23\0A.endif\0A.ifc $1,$$t8\0A.set .Ltrax_rt_${:uid}, 24\0A.endif\0A.ifc $1,$$t9\0A.set .Ltrax_rt_${:uid}, 25\0A.endif\0A.ifc $1,$$k0\0A.set .Ltrax_rt_${:uid}, 26\0A.endif\0A.ifc $1,$$k1\0A.set .Ltrax_rt_${:uid}, 27\0A.endif\0A.ifc $1,$$gp\0A.set .Ltrax_rt_${:uid}, 28\0A.endif\0A.ifc $1,$$sp\0A.set .Ltrax_rt_${:uid}, 29\0A.endif\0A.ifc $1,$$fp\0A.set .Ltrax_rt_${:uid}, 30\0A.endif\0A.ifc $1,$$ra\0A.set .Ltrax_rt_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $2,$$\\r\0A.set .Ltrax_rd_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $2,$$zero\0A.set .Ltrax_rd_${:uid}, 0\0A.endif\0A.ifc $2,$$at\0A.set .Ltrax_rd_${:uid}, 1\0A.endif\0A.ifc $2,$$v0\0A.set .Ltrax_rd_${:uid}, 2\0A.endif\0A.ifc $2,$$v1\0A.set .Ltrax_rd_${:uid}, 3\0A.endif\0A.ifc $2,$$a0\0A.set .Ltrax_rd_${:uid}, 4\0A.endif\0A.ifc $2,$$a1\0A.set .Ltrax_rd_${:uid}, 5\0A.endif\0A.ifc $2,$$a2\0A.set .Ltrax_rd_${:uid}, 6\0A.endif\0A.ifc $2,$$a3\0A.set .Ltrax_rd_${:uid}, 7\0A.endif\0A.ifc $2,$$t0\0A.set .Ltrax_rd_${:uid}, 8\0A.endif\0A.ifc $2,$$t1\0A.set .Ltrax_rd_${:uid}, 9\0A.endif\0A.ifc $2,$$t2\0A.set .Ltrax_rd_${:uid}, 10\0A.endif\0A.ifc $2,$$t3\0A.set .Ltrax_rd_${:uid}, 11\0A.endif\0A.ifc $2,$$t4\0A.set .Ltrax_rd_${:uid}, 12\0A.endif\0A.ifc $2,$$t5\0A.set .Ltrax_rd_${:uid}, 13\0A.endif\0A.ifc $2,$$t6\0A.set .Ltrax_rd_${:uid}, 14\0A.endif\0A.ifc $2,$$t7\0A.set .Ltrax_rd_${:uid}, 15\0A.endif\0A.ifc $2,$$s0\0A.set .Ltrax_rd_${:uid}, 16\0A.endif\0A.ifc $2,$$s1\0A.set .Ltrax_rd_${:uid}, 17\0A.endif\0A.ifc $2,$$s2\0A.set .Ltrax_rd_${:uid}, 18\0A.endif\0A.ifc $2,$$s3\0A.set .Ltrax_rd_${:uid}, 19\0A.endif\0A.ifc $2,$$s4\0A.set .Ltrax_rd_${:uid}, 20\0A.endif\0A.ifc $2,$$s5\0A.set .Ltrax_rd_${:uid}, 21\0A.endif\0A.ifc $2,$$s6\0A.set .Ltrax_rd_${:uid}, 22\0A.endif\0A.ifc $2,$$s7\0A.set .Ltrax_rd_${:uid}, 23\0A.endif\0A.ifc $2,$$t8\0A.set .Ltrax_rd_${:uid}, 24\0A.endif\0A.ifc $2,$$t9\0A.set .Ltrax_rd_${:uid}, 25\0A.endif\0A.ifc $2,$$k0\0A.set .Ltrax_rd_${:uid}, 26\0A.endif\0A.ifc $2,$$k1\0A.set .Ltrax_rd_${:uid}, 27\0A.endif\0A.ifc $2,$$gp\0A.set .Ltrax_rd_${:uid}, 28\0A.endif\0A.ifc $2,$$sp\0A.set .Ltrax_rd_${:uid}, 29\0A.endif\0A.ifc $2,$$fp\0A.set .Ltrax_rd_${:uid}, 30\0A.endif\0A.ifc $2,$$ra\0A.set .Ltrax_rd_${:uid}, 31\0A.endif\0A.word 0x7000001d | (.Ltrax_rs_${:uid} << 21) | (.Ltrax_rt_${:uid} << 16) | (.Ltrax_rd_${:uid} << 11)\0A.set pop", "r,r,r"(i32 257, i32 %7, i32 16)
  unreachable

check.ok:                                         ; preds = %start
  %8 = getelementptr inbounds [3 x i32], [3 x i32]* @"consts::TABLE", i32 0, i32 %2
  %9 = load i32, i32* %8, align 4
  %10 = load i32, i32* @"consts::LIMIT", align 4
  %11 = add i32 %9, %10
  call void @"trax::store_u32"(i32 0, i32 %11)
  ret void
}

