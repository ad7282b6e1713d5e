/* placeholder */ typedef int placeholder_long_double_reference;
