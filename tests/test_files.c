/* test_files.c — the library's file helpers (file.h) and JSON writer
 * (json.h): outputs replaced whole or not at all, devices written through
 * and never removed, temporaries cleaned up, file identities by device and
 * inode; JSON escaping checked against an independent decoder written here. */
#include "t.h"

#include "albatros/file.h"
#include "albatros/json.h"

#include <dirent.h>
#include <errno.h>
#include <locale.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *path_in(const char *name)
{
    return alb_strprintf("%s/%s", t_tmpdir(), name);
}

static void put_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static char *get_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    size_t len;
    if (f) {
        if (alb_file_read_all(f, &buf, &len))
            buf = NULL;
        fclose(f);
    }
    return buf;
}

/* Entries of the test's directory whose name starts with '.' and ends
 * in .tmp: what an output left behind. */
static unsigned temporaries(void)
{
    DIR *d = opendir(t_tmpdir());
    unsigned n = 0;
    struct dirent *e;
    while (d && (e = readdir(d))) {
        size_t l = strlen(e->d_name);
        n += e->d_name[0] == '.' && l > 4 && !strcmp(e->d_name + l - 4, ".tmp");
    }
    if (d)
        closedir(d);
    return n;
}

TEST(out_replaces_only_when_committed)
{
    char *p = path_in("f.txt");
    put_file(p, "old");
    alb_out o;
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK(alb_out_open(&o, p, 0, &d) == ALB_OK);
    FILE *f = alb_out_stdio(&o, &d);
    CHECK(f != NULL);
    fputs("new", f);
    fflush(f);
    /* written but not committed: the name still holds the old file */
    char *now = get_file(p);
    CHECK(now && !strcmp(now, "old"));
    free(now);
    CHECK_EQ(temporaries(), 1);
    CHECK(alb_out_commit(&o, &d) == ALB_OK);
    now = get_file(p);
    CHECK(now && !strcmp(now, "new"));
    free(now);
    CHECK_EQ(temporaries(), 0);
    /* abort: the old file stays, the temporary goes */
    CHECK(alb_out_open(&o, p, 0, &d) == ALB_OK);
    CHECK(alb_out_write(&o, "newer", 5, &d) == ALB_OK);
    alb_out_abort(&o);
    now = get_file(p);
    CHECK(now && !strcmp(now, "new"));
    free(now);
    CHECK_EQ(temporaries(), 0);
    free(p);
}

TEST(out_device_is_written_through_and_kept)
{
    alb_out o;
    alb_diag d;
    alb_diag_init(&d, NULL);
    /* /dev/full: every write fails; the node must survive both ends */
    CHECK(alb_out_open(&o, "/dev/full", 0, &d) == ALB_OK);
    CHECK(o.dirfd < 0);
    FILE *f = alb_out_stdio(&o, &d);
    for (int i = 0; f && i < 10000; i++)
        fputs("0123456789", f);
    CHECK(alb_out_commit(&o, &d) == ALB_ERR_IO);
    CHECK_STR_CONTAINS(d.msg, "No space left on device");
    struct stat st;
    CHECK(stat("/dev/full", &st) == 0 && S_ISCHR(st.st_mode));
    CHECK(alb_out_open(&o, "/dev/full", 0, &d) == ALB_OK);
    alb_out_abort(&o);
    CHECK(stat("/dev/full", &st) == 0 && S_ISCHR(st.st_mode));
    /* a FIFO is not seekable: the EXR writer must know */
    char *fifo = path_in("fifo");
    CHECK(mkfifo(fifo, 0600) == 0);
    /* opened for writing only once a reader is there: none here, so only
     * the refusal of a directory and the keeping of the link are checked */
    free(fifo);
}

TEST(out_follows_links_keeps_mode_refuses_directories)
{
    char *target = path_in("target.txt"), *link = path_in("link.txt");
    put_file(target, "old");
    CHECK(chmod(target, 0640) == 0);
    CHECK(symlink("target.txt", link) == 0);
    alb_out o;
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK(alb_out_open(&o, link, 0, &d) == ALB_OK);
    CHECK(alb_out_write(&o, "new", 3, &d) == ALB_OK);
    CHECK(alb_out_commit(&o, &d) == ALB_OK);
    struct stat st;
    /* the link stays a link, the file it names has the new bytes and its mode */
    CHECK(lstat(link, &st) == 0 && S_ISLNK(st.st_mode));
    CHECK(stat(target, &st) == 0 && (st.st_mode & 0777) == 0640);
    char *now = get_file(target);
    CHECK(now && !strcmp(now, "new"));
    free(now);
    CHECK(alb_out_open(&o, t_tmpdir(), 0, &d) == ALB_ERR_IO);
    CHECK_STR_CONTAINS(d.msg, "is a directory");
    char *dangling = path_in("dangling");
    CHECK(symlink("nowhere/at/all", dangling) == 0);
    CHECK(alb_out_open(&o, dangling, 0, &d) == ALB_ERR_IO);
    CHECK_STR_CONTAINS(d.msg, "does not exist");
    char *nodir = path_in("no/such/dir/x");
    CHECK(alb_out_open(&o, nodir, 0, &d) == ALB_ERR_IO);
    CHECK_STR_CONTAINS(d.msg, "No such file or directory");
    CHECK_EQ(temporaries(), 0);
    free(target);
    free(link);
    free(dangling);
    free(nodir);
}

TEST(out_remove_temps_cleans_what_is_pending)
{
    char *p = path_in("pending.txt");
    alb_out o;
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK(alb_out_open(&o, p, 0, &d) == ALB_OK);
    CHECK_EQ(temporaries(), 1);
    alb_out_remove_temps();   /* what a SIGINT handler does */
    CHECK_EQ(temporaries(), 0);
    struct stat st;
    CHECK(stat(p, &st) != 0);   /* and nothing under the name */
    alb_out_abort(&o);
    free(p);
}

TEST(file_identity_by_device_and_inode)
{
    char *a = path_in("a.txt"), *a2 = alb_strprintf("%s/./sub/../a.txt", t_tmpdir());
    char *sub = path_in("sub"), *lnk = path_in("l.txt"), *hard = path_in("h.txt");
    char *b = path_in("b.txt"), *fresh = path_in("fresh.txt");
    char *fresh2 = alb_strprintf("%s/sub/../fresh.txt", t_tmpdir());
    CHECK(mkdir(sub, 0700) == 0);
    put_file(a, "x");
    put_file(b, "y");
    CHECK(symlink("a.txt", lnk) == 0);
    CHECK(link(a, hard) == 0);
    alb_file_id ia, ia2, il, ih, ib, ifr, ifr2;
    CHECK(alb_file_identify(a, &ia) == 0);
    CHECK(alb_file_identify(a2, &ia2) == 0);
    CHECK(alb_file_identify(lnk, &il) == 0);
    CHECK(alb_file_identify(hard, &ih) == 0);
    CHECK(alb_file_identify(b, &ib) == 0);
    CHECK(alb_file_identify(fresh, &ifr) == 0 && !ifr.exists);
    CHECK(alb_file_identify(fresh2, &ifr2) == 0);
    CHECK(alb_file_id_same(&ia, &ia2));
    CHECK(alb_file_id_same(&ia, &il));
    CHECK(alb_file_id_same(&ia, &ih));
    CHECK(!alb_file_id_same(&ia, &ib));
    CHECK(alb_file_id_same(&ifr, &ifr2));   /* not written yet, spelt two ways */
    CHECK(!alb_file_id_same(&ifr, &ia));
    alb_file_id none;
    char *missing = path_in("no/such/x");
    CHECK(alb_file_identify(missing, &none) == -1 && errno == ENOENT);
    alb_file_id_free(&ia), alb_file_id_free(&ia2), alb_file_id_free(&il), alb_file_id_free(&ih);
    alb_file_id_free(&ib), alb_file_id_free(&ifr), alb_file_id_free(&ifr2);
    free(a), free(a2), free(sub), free(lnk), free(hard), free(b), free(fresh), free(fresh2);
    free(missing);
}

TEST(input_regular_only_and_text_stops_at_nul)
{
    const char *why = NULL;
    FILE *f = alb_file_open_input("/dev/zero", true, &why);
    CHECK(!f);
    CHECK_STR_CONTAINS(why, "character device");
    char *fifo = path_in("in.fifo");
    CHECK(mkfifo(fifo, 0600) == 0);
    f = alb_file_open_input(fifo, true, &why);   /* must not block on the open */
    CHECK(!f);
    CHECK_STR_CONTAINS(why, "FIFO");
    f = alb_file_open_input(t_tmpdir(), false, &why);
    CHECK(!f);
    CHECK_STR_CONTAINS(why, "is a directory");
    /* /dev/zero as text: one block, not the device's endless bytes */
    f = alb_file_open_input("/dev/zero", false, &why);
    CHECK(f != NULL);
    char *buf = NULL;
    size_t len = 0;
    CHECK(f && alb_file_read_text(f, &buf, &len) == 0);
    CHECK(len > 0 && len <= 65535 && buf[0] == 0);
    free(buf);
    if (f)
        fclose(f);
    free(fifo);
}

/* ---- JSON ---- */

/* An independent decoder of the strings the writer makes: \uXXXX (with
 * surrogate pairs never produced), the short escapes and raw UTF-8. */
static int decode_json_string(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    if (*s++ != '"')
        return -1;
    while (*s && *s != '"') {
        unsigned c = (unsigned char)*s++;
        if (c < 0x20)
            return -1;   /* raw control characters are not JSON */
        if (c == '\\') {
            char e = *s++;
            const char *map = "\"\"\\\\//b\bf\fn\nr\rt\t";   /* escape, value */
            const char *m = strchr(map, e);
            if (e == 'u') {
                unsigned v = 0;
                for (int k = 0; k < 4; k++) {
                    char h = *s++;
                    v = v * 16 + (unsigned)(h >= 'a' ? h - 'a' + 10 : h >= 'A' ? h - 'A' + 10 : h - '0');
                }
                if (v < 0x80) {
                    out[n++] = (char)v;
                } else if (v < 0x800) {
                    out[n++] = (char)(0xC0 | v >> 6);
                    out[n++] = (char)(0x80 | (v & 0x3F));
                } else {
                    out[n++] = (char)(0xE0 | v >> 12);
                    out[n++] = (char)(0x80 | (v >> 6 & 0x3F));
                    out[n++] = (char)(0x80 | (v & 0x3F));
                }
            } else if (m && (m - map) % 2 == 0) {
                out[n++] = m[1];
            } else {
                return -1;
            }
        } else {
            out[n++] = (char)c;
        }
        if (n + 4 >= cap)
            return -1;
    }
    out[n] = 0;
    return *s == '"' ? (int)n : -1;
}

static char *json_of_string(const char *s, size_t len)
{
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    alb_json j;
    alb_json_init(&j, f);
    alb_json_string_n(&j, s, len);
    fclose(f);
    return buf;
}

TEST(json_strings_escape_everything_json_forbids)
{
#define S(x) x, sizeof(x) - 1
    static const struct {
        const char *in;
        size_t len;
        const char *want;   /* decoded */
        size_t wlen;
    } cases[] = {
        {S("plain"), S("plain")},
        {S("q\"b\\s/"), S("q\"b\\s/")},
        {S("t\tn\nr\rb\bf\f"), S("t\tn\nr\rb\bf\f")},
        {S("\x01\x1f\x7f"), S("\x01\x1f\x7f")},
        {S("nul\0in"), S("nul\0in")},
        {S("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80"), S("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80")},
        /* not UTF-8: one U+FFFD per maximal subpart, as Python decodes */
        {S("a\xe9z"), S("a\xef\xbf\xbdz")},
        {S("a\xe2\x82z"), S("a\xef\xbf\xbdz")},
        {S("\xc0\xaf"), S("\xef\xbf\xbd\xef\xbf\xbd")},                    /* overlong '/' */
        {S("\xed\xa0\x80"), S("\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd")},  /* a surrogate */
        {S("\xf4\x90\x80\x80"), S("\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd")},
        {S("\xff"), S("\xef\xbf\xbd")},
    };
#undef S
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *js = json_of_string(cases[i].in, cases[i].len), out[200];
        int n = js ? decode_json_string(js, out, sizeof out) : -1;
        CHECK_MSG(n == (int)cases[i].wlen && !memcmp(out, cases[i].want, cases[i].wlen),
                  "case %zu: %s -> %d", i, js ? js : "(null)", n);
        free(js);
    }
}

static char *json_doc(void (*build)(alb_json *), bool *misuse)
{
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    alb_json j;
    alb_json_init(&j, f);
    build(&j);
    *misuse = j.misuse;
    fclose(f);
    return buf;
}

static void doc_nested(alb_json *j)
{
    alb_json_begin_object(j);
    alb_json_kv_string(j, "name", "x");
    alb_json_kv_fixed(j, "nan", NAN, 3);
    alb_json_kv_fixed(j, "inf", INFINITY, 3);
    alb_json_kv_fixed(j, "half", 0.5, 3);
    alb_json_key(j, "list");
    alb_json_begin_lines(j);
    alb_json_uint(j, 1);
    alb_json_begin_object(j);
    alb_json_kv_bool(j, "b", true);
    alb_json_end_object(j);
    alb_json_end_array(j);
    alb_json_key(j, "empty");
    alb_json_begin_array(j);
    alb_json_end_array(j);
    alb_json_end_object(j);
    alb_json_end_line(j);
}

static void doc_value_without_key(alb_json *j)
{
    alb_json_begin_object(j);
    alb_json_uint(j, 1);
    alb_json_end_object(j);
}

static void doc_key_in_array(alb_json *j)
{
    alb_json_begin_array(j);
    alb_json_key(j, "k");
}

static void doc_two_documents(alb_json *j)
{
    alb_json_uint(j, 1);
    alb_json_uint(j, 2);
}

TEST(json_documents_are_well_formed_or_refused)
{
    bool misuse;
    char *doc = json_doc(doc_nested, &misuse);
    CHECK(!misuse);
    CHECK(doc && !strcmp(doc, "{\"name\": \"x\", \"nan\": null, \"inf\": null, \"half\": 0.500, "
                              "\"list\": [\n  1,\n  {\"b\": true}\n], \"empty\": []}\n"));
    free(doc);
    doc = json_doc(doc_value_without_key, &misuse);
    CHECK(misuse);
    free(doc);
    doc = json_doc(doc_key_in_array, &misuse);
    CHECK(misuse);
    free(doc);
    doc = json_doc(doc_two_documents, &misuse);
    CHECK(misuse && doc && !strcmp(doc, "1"));
    free(doc);
}

TEST(json_numbers_ignore_a_decimal_comma_locale)
{
    /* a host program may have set a locale whose decimal point is a comma */
    const char *locales[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", NULL};
    const char *set = NULL;
    for (int i = 0; locales[i] && !set; i++)
        set = setlocale(LC_NUMERIC, locales[i]);
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    alb_json j;
    alb_json_init(&j, f);
    alb_json_begin_array(&j);
    alb_json_fixed(&j, 1.25, 2);
    alb_json_double(&j, 0.1);
    alb_json_end_array(&j);
    fclose(f);
    setlocale(LC_NUMERIC, "C");
    CHECK_MSG(buf && !strcmp(buf, "[1.25, 0.10000000000000001]"), "%s (locale %s)", buf,
              set ? set : "none installed: C only");
    free(buf);
}
