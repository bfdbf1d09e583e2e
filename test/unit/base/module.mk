# test/unit/base: one CMocka program per src/core/base module (also built for the
# 68040 by make test-cross); they see the core alone
$(eval $(call unit_tests,base))
