/* embed.c — turns a text file into a C array, so the built-in scene ships
 * inside the albatros binary (no xxd needed on a fresh machine). */
#include <stdio.h>

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: embed SYMBOL INPUT OUTPUT.c\n");
        return 2;
    }
    FILE *in = fopen(argv[2], "rb");
    if (!in) {
        perror(argv[2]);
        return 1;
    }
    FILE *out = fopen(argv[3], "w");
    if (!out) {
        perror(argv[3]);
        fclose(in);
        return 1;
    }
    fprintf(out, "/* generated from %s by tools/embed.c; do not edit */\n"
                 "#include <stddef.h>\nconst char %s[] = {\n", argv[2], argv[1]);
    int c;
    unsigned long n = 0;
    while ((c = fgetc(in)) != EOF) {
        fprintf(out, "%d,%s", c, ++n % 20 ? "" : "\n");
    }
    fprintf(out, "0};\nconst size_t %s_len = %lu;\n", argv[1], n);
    int bad = ferror(in) || ferror(out);
    fclose(in);
    if (fclose(out) || bad) {
        fprintf(stderr, "embed: write failed\n");
        remove(argv[3]);
        return 1;
    }
    return 0;
}
